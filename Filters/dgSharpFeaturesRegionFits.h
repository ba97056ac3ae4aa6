// What the sharp-features stage (dgSharpFeatures.h) fits to the smooth
// regions on either side of AT's bands: local samples of a region near a
// band face, and the whole-region models (planes, quadrics) that take
// their place when the region is large enough to be sure of one. Internal
// to that stage; docs/sharp-features.md says why each model is there.
#ifndef dgSharpFeaturesRegionFits_h
#define dgSharpFeaturesRegionFits_h

#include "dgSharpFeaturesGraph.h"

#include <Eigen/Core>

#include <vector>

namespace dg
{
namespace sharp
{

// What a band face's search found of one region (positions relative to
// the band face, to keep the moments' numbers small).
struct RegionSample
{
  int Region = -1;
  int Count = 0;
  Vec3 CentroidSum, NormalSum;
  double Moment[6] = { 0, 0, 0, 0, 0, 0 }; // sums of xx, xy, xz, yy, yz, zz
  Eigen::Matrix3d NormalMoment = Eigen::Matrix3d::Zero(); // sum of u x^T
  double NormalSquares = 0;                                // sum of |u|^2
  double QuadricDistanceSum = 0; // sum of the faces' distances to their region's quadric

  void AddPosition(const Vec3& p)
  {
    this->CentroidSum += p;
    this->Moment[0] += p.x * p.x;
    this->Moment[1] += p.x * p.y;
    this->Moment[2] += p.x * p.z;
    this->Moment[3] += p.y * p.y;
    this->Moment[4] += p.y * p.z;
    this->Moment[5] += p.z * p.z;
  }

  void AddNormal(const Vec3& u, const Vec3& p)
  {
    this->NormalSum += u;
    this->NormalMoment += Eigen::Vector3d(u.x, u.y, u.z) * Eigen::RowVector3d(p.x, p.y, p.z);
    this->NormalSquares += u.Dot(u);
  }

  Eigen::Matrix3d Covariance() const; // of the positions
  // The linear fit u(x) = mean + S (x - c) of the normals to the positions:
  // returns S, and the normals' cross-covariance with the positions in cux.
  Eigen::Matrix3d NormalSlope(const Eigen::Matrix3d& cov, Eigen::Matrix3d& cux) const;
  // S restricted to the plane of unit normal m, and symmetrised.
  static Eigen::Matrix3d InPlane(const Eigen::Matrix3d& S, const Eigen::Vector3d& m);
  // How far the side's surface falls below its plane (unit normal m) at p.
  double Fall(const Vec3& m, const Vec3& p) const;
  // The normal of the least-squares plane through the positions.
  Vec3 PlaneNormal(double maxResidual2) const;
};

// A region whose normal field turns by less than a given angle across it:
// the plane through all its faces.
struct RegionPlane
{
  bool Planar = false;
  Vec3 Normal, Point;
};

// region: per face, its region (0..regions-1) or -1; centre, field: per
// face, its centre and unit normal. A region is tested when it has at least
// minimumSize faces and its positions spread by at least minimumExtent
// (square root of the covariance's largest eigenvalue).
std::vector<RegionPlane> FindPlanarRegions(const std::vector<int>& region, int regions,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& field, int minimumSize,
  double minimumExtent, double maximumTurnDegrees);

// The quadric Q(x) = 0 fitted to all a region's faces, positions and
// normals together; Distance is Q / |grad Q| (its first-order signed
// distance), positive on the side the normals point to.
struct RegionQuadric
{
  bool Valid = false;
  Vec3 Centre;       // the faces' centroid
  double Scale = 1;  // coordinates are (x - Centre) / Scale
  Eigen::Matrix<double, 10, 1> Coefficients = Eigen::Matrix<double, 10, 1>::Zero();
  double Distance(const Vec3& x) const;
  Vec3 Normal(const Vec3& x) const; // grad Q / |grad Q| (zero where grad Q is)
};

// Quadrics for the regions with at least minimumSize faces, a face at least
// minimumExtent from their centroid and skip[r] == 0. unit: the length
// in which a position residual weighs as much as a normal residual of one
// radian (the mean edge).
std::vector<RegionQuadric> FitRegionQuadrics(const std::vector<int>& region, int regions,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& field, const std::vector<char>& skip,
  int minimumSize, double minimumExtent, double unit);

// The quadrics (as FitRegionQuadrics) of the regions with wanted[r] != 0,
// kept Valid only where the RMS distance of the region's faces to it is at
// most maxResidual: the region is that quadric to within the staircase.
std::vector<RegionQuadric> FitQuadricSides(const std::vector<int>& region, int regions,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& field, const std::vector<char>& wanted,
  int minimumSize, double minimumExtent, double unit, double maxResidual);

// The same fit for one set of faces (at least 10), scaled by their own
// extent.
RegionQuadric FitQuadric(const std::vector<std::int64_t>& faces, const std::vector<Vec3>& centre,
  const std::vector<Vec3>& field, double unit);

} // namespace sharp
} // namespace dg

#endif
