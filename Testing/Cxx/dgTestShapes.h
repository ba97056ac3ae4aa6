// Shapes and helpers shared by the C++ tests: volumes built from implicit
// functions (so that true normals and sharp edges are known), random voxel
// sets, and an observer that records VTK errors and warnings.
#ifndef dgTestShapes_h
#define dgTestShapes_h

#include <Eigen/Core>

#include <vtkAlgorithm.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace dgtest
{

/// An image of nx*ny*nz voxels (extent from 0, origin 0, spacing 1) whose
/// point scalars (type vtkType) hold value(i, j, k).
vtkSmartPointer<vtkImageData> MakeImage(int nx, int ny, int nz,
  const std::function<double(int, int, int)>& value, int vtkType = VTK_UNSIGNED_CHAR);

/// Digitises an implicit shape: voxel (i, j, k) is inside (value 1) when
/// inside(i, j, k) holds at its centre (grid coordinates).
vtkSmartPointer<vtkImageData> Digitize(
  int n, const std::function<bool(double, double, double)>& inside);

/// A digitised ball of radius r centred in an n^3 image (centre slightly off
/// the grid so that no voxel centre sits exactly on the sphere).
vtkSmartPointer<vtkImageData> Ball(int n, double r);

/// Random voxel set: each voxel inside with probability p.
vtkSmartPointer<vtkImageData> RandomVoxels(int nx, int ny, int nz, double p, unsigned seed);

/// A 3 x 3 grid of unit quads in the plane z = 0 (points 0..15, row-major,
/// point (i, j) lifted by zWiggle when i + j is odd), wound counter-clockwise
/// except the centre quad when reverseCentre; no attribute arrays.
vtkSmartPointer<vtkPolyData> QuadGrid3x3(bool reverseCentre, double zWiggle = 0.0);

/// A flat nx x ny grid of unit quads (or two triangles per square) in z = 0
/// with a cell array "Step": 0 left of x = jump, 1 right of it.
vtkSmartPointer<vtkPolyData> FlatSquare(int nx, int ny, double jump, bool triangles);

/// The line cells of a feature-edge output as (smaller id, larger id) pairs,
/// sorted: two outputs on the same points compare edge for edge.
std::vector<std::pair<vtkIdType, vtkIdType>> EdgePairs(vtkPolyData* lines);

/// The centre (mean of its points) of every cell, in world coordinates.
std::vector<Eigen::Vector3d> CellCentres(vtkPolyData* pd);

/// A copy of the points pressed into the plane z = 0 (degenerate geometry).
vtkSmartPointer<vtkPoints> FlattenedPoints(vtkPoints* points);

/// The surface with every polygon's winding reversed and its cell data
/// left as it was: the sharp stage's CreaseSides bits then name the wrong
/// sides (a filter that reordered corners after it).
vtkSmartPointer<vtkPolyData> ReversedKeepingCellData(vtkPolyData* surface);

/// Updates `algorithm` and tells whether it refused its input as the
/// module's filters must: exactly one error, mentioning `words`, and every
/// output port empty (no cells). Otherwise `why` says what happened.
bool RefusedWith(vtkAlgorithm* algorithm, const std::string& words, std::string* why);

/// Records errors and warnings emitted by a VTK object.
class ErrorObserver : public vtkCommand
{
public:
  static ErrorObserver* New() { return new ErrorObserver; }
  void Execute(vtkObject*, unsigned long event, void* data) override;
  void Observe(vtkObject* o);
  void Clear();
  int Errors = 0;
  int Warnings = 0;
  std::string Messages;
};

} // namespace dgtest

#endif
