// Implicit shapes with known outward normals and known sharp edges, for
// ground-truth comparisons. Coordinates are grid coordinates: voxel (i, j, k)
// has its centre at (i, j, k) (image origin 0, spacing 1).
//
// The "true normal" at a point p near the surface is the gradient direction
// of the shape's max-combined signed function at p: for a convex polyhedron,
// the normal of the face plane that p is closest to (largest n.p - d); for a
// sphere, the radial direction; for intersections, the normal of the part
// whose function is largest. Sharp edges are stored as dense polylines.
#ifndef dgGroundTruth_h
#define dgGroundTruth_h

#include <Eigen/Dense>
#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <array>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace dgtest
{

/// Distance from points to a set of segments, accelerated by a bucket grid.
class PolylineDistance
{
public:
  void AddSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
  /// Exact distance when it is below maxDistance; otherwise some value
  /// >= maxDistance (infinity when there is no segment within reach).
  double Distance(const Eigen::Vector3d& p, double maxDistance = 4.0) const;
  std::size_t Size() const { return this->A.size(); }
  double TotalLength() const;

private:
  void Build() const;
  std::vector<Eigen::Vector3d> A, B;
  // The bucket grid is built on first use; the flag makes concurrent
  // Distance() calls (vtkSMPTools loops in tests and benchmarks) safe.
  // Shared so that the class stays copyable; AddSegment replaces it.
  std::shared_ptr<std::once_flag> BuildOnce = std::make_shared<std::once_flag>();
  mutable double Cell = 4.0;
  mutable std::vector<std::vector<int>> Buckets;
  mutable Eigen::Vector3i GridMin, GridSize;
};

class ImplicitShape
{
public:
  virtual ~ImplicitShape() = default;
  virtual std::string Name() const = 0;
  /// Signed function: < 0 inside (a distance for spheres and planes, a
  /// max-combination of distances for CSG).
  virtual double Value(const Eigen::Vector3d& p) const = 0;
  bool Inside(const Eigen::Vector3d& p) const { return this->Value(p) <= 0.0; }
  /// True outward unit normal at (the surface point nearest to) p.
  virtual Eigen::Vector3d Normal(const Eigen::Vector3d& p) const = 0;
  /// Distance from p to the nearest sharp edge (infinity if the shape has none).
  double DistanceToSharpEdge(const Eigen::Vector3d& p, double maxDistance = 4.0) const
  {
    return this->Edges.Size() ? this->Edges.Distance(p, maxDistance)
                              : std::numeric_limits<double>::infinity();
  }
  /// Points every `step` along the sharp edges.
  std::vector<Eigen::Vector3d> SharpEdgeSamples(double step) const;
  const PolylineDistance& SharpEdges() const { return this->Edges; }
  /// Sharp edges as polylines (for sampling).
  std::vector<std::vector<Eigen::Vector3d>> EdgePolylines;

protected:
  void AddPolyline(const std::vector<Eigen::Vector3d>& line);
  PolylineDistance Edges;
};

std::unique_ptr<ImplicitShape> MakeSphere(const Eigen::Vector3d& center, double radius);
/// A cube of half side h, rotated by ax, ay, az degrees about x, y, z (R = Rz Ry Rx).
std::unique_ptr<ImplicitShape> MakeRotatedCube(
  const Eigen::Vector3d& center, double h, double ax, double ay, double az);
/// Intersection of an axis-aligned cube (half side h) and a concentric sphere of
/// radius r, h < r < h*sqrt(2): six flat discs joined by spherical parts; the
/// sharp edges are the six circles where the sphere meets the faces.
std::unique_ptr<ImplicitShape> MakeCubeSphere(const Eigen::Vector3d& center, double h, double r);
/// The same with each face at its own distance from the centre, in the
/// order +x, -x, +y, -y, +z, -z.
std::unique_ptr<ImplicitShape> MakeCubeSphere(
  const Eigen::Vector3d& center, const std::array<double, 6>& h, double r);
/// A cylinder along z with flat caps: radius r, half height hz.
std::unique_ptr<ImplicitShape> MakeCylinder(const Eigen::Vector3d& center, double r, double hz);
/// |x| + |y| + |z| <= a (dihedral angle 109.47 degrees).
std::unique_ptr<ImplicitShape> MakeOctahedron(const Eigen::Vector3d& center, double a);
/// A roof: box |x| <= h, |y| <= h, -h <= z <= h - tan(15 deg) |x|; the ridge
/// (x = 0) has a dihedral angle of 150 degrees (the paper's vanishing features).
std::unique_ptr<ImplicitShape> MakeWedge(const Eigen::Vector3d& center, double h);

/// Smooth shapes, rotated by ax, ay, az degrees (R = Rz Ry Rx) about their
/// centre: a torus (major and minor radius, axis z), an ellipsoid (semi-axes
/// along x, y, z) and a box of half sides `half` whose edges and corners are
/// rounded with `radius` (a fillet; radius 0 is the sharp box).
std::unique_ptr<ImplicitShape> MakeTorus(
  const Eigen::Vector3d& center, double major, double minor, double ax, double ay, double az);
std::unique_ptr<ImplicitShape> MakeEllipsoid(
  const Eigen::Vector3d& center, const Eigen::Vector3d& axes, double ax, double ay, double az);
std::unique_ptr<ImplicitShape> MakeRoundedBox(const Eigen::Vector3d& center,
  const Eigen::Vector3d& half, double radius, double ax, double ay, double az);
/// A box of half sides `half` whose eight edges around its two z faces are
/// rounded with `radius` and whose four edges along z are sharp (a
/// machined part's mix: sharp edges that end in fillets), rotated as
/// above; its sharp edges are the four straight ones, where both sides are
/// flat.
std::unique_ptr<ImplicitShape> MakeMixedBox(const Eigen::Vector3d& center,
  const Eigen::Vector3d& half, double radius, double ax, double ay, double az);
/// A smooth union of balls (centres, radii): the zero set of the soft
/// minimum -s log sum_i exp(-(|x - c_i| - r_i) / s) of their distances, with
/// necks where two balls meet and saddles where three do; `blend` is s.
std::unique_ptr<ImplicitShape> MakeBlobs(const std::vector<Eigen::Vector3d>& centers,
  const std::vector<double>& radii, double blend);
/// The smooth and filleted test shapes by name, scaled to an n^3 grid
/// (TestSmoothShapes and BenchQuality measure the same ones): "torus",
/// "torus2" (minor radius 0.16 n, two orientations), "sphere" (radius
/// 0.19 n), "ellipsoid", "ellipsoid2", "filletR" (a rotated box whose edges
/// are rounded with radius R voxels, R in 2..12), "prismNrR" (a right prism
/// over a regular N-gon, N = 6, 8 or 12, apothem 0.3 n, half height 0.22 n,
/// rotated as the boxes, its edges rounded with radius R in 2..12: the
/// lateral edges turn by 360 / N degrees) and "blobs" (five balls in
/// a smooth union: necks and saddles, curvature radius >= 7 voxels at 64^3).
/// nullptr for any other name.
std::unique_ptr<ImplicitShape> MakeSmoothShape(const std::string& name, int n);

/// Digitises a shape in an n^3 unsigned char image (1 inside, 0 outside).
vtkSmartPointer<vtkImageData> Digitize(const ImplicitShape& shape, int n);
/// The same with the paper's noise of level k (dg::ApplyNoise, given seed).
vtkSmartPointer<vtkImageData> NoisyDigitize(
  const ImplicitShape& shape, int n, double k, std::uint64_t seed);

/// Centre of each surfel of a vtkDigitalSurfaceFilter output, in grid
/// coordinates (inside voxel + half a voxel along the direction).
std::vector<Eigen::Vector3d> SurfelCenters(vtkDataObject* digitalSurface);

/// Angle in degrees between two vectors (0..180).
double AngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

} // namespace dgtest

#endif
