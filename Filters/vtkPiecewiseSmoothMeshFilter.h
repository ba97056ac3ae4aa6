/**
 * @class   vtkPiecewiseSmoothMeshFilter
 * @brief   A mesh whose faces follow a piecewise-smooth normal field, with
 *          the sharp features as creases: the digital surface's vertices
 *          moved, a stage after vtkSharpFeaturesFilter.
 *
 * The digital surface is a staircase of voxel faces; the earlier stages
 * give it good normals but leave its vertices on the voxel corners. This
 * filter moves each vertex, within its voxel corner's cell (at most half a
 * voxel along each image axis, so that no two vertices can cross), so that
 * every face becomes orthogonal to its normal (array 0, default
 * "SharpNormals"), each crease straightens along itself, and the mesh stays
 * near the digital surface. The creases are the sharp stage's feature
 * edges, read from its cell data "CreaseSides" (array 2: per face, bit i
 * set when the side from corner i to corner i + 1 is a feature edge) when
 * the input has it; otherwise the edges between two feature regions
 * (array 1, default "FeatureRegion", the sharp stage's smooth parts, or any
 * region ids of your own). The sides come first because the sharp stage
 * may leave a stretch of a region boundary undrawn (a sharp edge that
 * fades into a fillet), which the regions alone would make a crease. The
 * sides are named by the faces' corner order: a filter between the two
 * stages that reorders corners (reverses a face's winding, triangulates)
 * must drop that array or remap its bits (bits that no longer match, an
 * edge flagged by one of its two faces only, are an error). The energy
 * is quadratic in the positions: one sparse symmetric system, solved by
 * conjugate gradients, with the cell bound kept by ADMM (an inequality
 * split off the energy, whose result is always within the cells)
 * (docs/mesh.md states the energy, the bound and why).
 *
 * Smoothing acts along a crease, never across it: no term couples the two
 * sides' normals, so a rotated cube keeps its edges and corners.
 *
 * Input: a digital surface (vtkDigitalSurfaceFilter's output or any stage
 * after it: every polygon side one voxel step along an image axis) with a
 * unit cell normal field. Without the crease sides and the region array
 * the mesh has no crease.
 * Label-map interfaces (cell data "LabelInside" and "LabelOutside") split
 * the regions further by label pair, so that the lines where three labels
 * meet are creases; shared vertices move once, so every interface stays
 * shared by its two labels.
 *
 * Output port 0: the moved surface, quads (or triangles with
 * OutputTriangles, each quad split along the diagonal whose triangles
 * follow its normal best), the input's cell data (repeated for the two
 * triangles of a quad) and point data; point data "MeshDisplacement" (the
 * world vector each vertex moved) and "Normals" (active): with
 * SplitFeaturePoints (default on), each vertex on a crease is repeated once
 * per side around it and takes that side's normal (the area-weighted mean
 * of the field over its faces there), so that smooth shading shows crisp
 * edges; point data "GlobalIds", when present, keeps the original
 * point's id so the copies can be merged again.
 * Output port 1: the creases, each crease edge once, as lines
 * on the moved positions, with cell data "FeatureAngle" (degrees between
 * the normals of the faces across the edge).
 *
 * Parameters are in voxels. Bad input (no polygons, a surface that is not
 * one of voxel faces, a missing, wrongly sized or non-unit normal field,
 * crease sides that do not match the corners, parameters out of range)
 * gives an error and empty outputs.
 *
 * Pieces: under a multi-process controller each process moves the
 * vertices of its own faces (the input's non-ghost cells, matched across
 * pieces by their cell and point "GlobalIds"): it fetches the faces around
 * its points from the other pieces, and all vertices are solved as one
 * distributed system over vtkMultiProcessController (the halo
 * vtkAmbrosioTortorelliFilter's solve uses). Each process outputs its own
 * faces and the creases whose end of smaller global id it owns; positions
 * and normals equal one process's to the solver's tolerance.
 */
#ifndef vtkPiecewiseSmoothMeshFilter_h
#define vtkPiecewiseSmoothMeshFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>

class VTKDIGITALGEOMETRY_EXPORT vtkPiecewiseSmoothMeshFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkPiecewiseSmoothMeshFilter* New();
  vtkTypeMacro(vtkPiecewiseSmoothMeshFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * How strongly each vertex stays at its voxel corner along its normal
   * (> 0, default 0.05), against weight 1 per face side for the faces'
   * orthogonality: it decides where each smooth part lies (the mean of its
   * corners). Small values let the creases' staircase pull whole faces
   * inwards; large ones keep the staircase.
   */
  vtkSetMacro(DataWeight, double);
  vtkGetMacro(DataWeight, double);
  ///@}

  ///@{
  /**
   * Weight of a crease edge's straightness along the crease (>= 0,
   * default 1), against weight 1 per face side; 0 leaves the creases to the
   * faces alone.
   */
  vtkSetMacro(CreaseWeight, double);
  vtkGetMacro(CreaseWeight, double);
  ///@}

  ///@{
  /**
   * Iterations (>= 1, default 16). The faces' orthogonality couples the
   * coordinates and the cell bound is an inequality; each iteration solves
   * one linear system that agrees with both at the current positions
   * (docs/mesh.md). On a rotated cube the faces' mean deviation from their
   * normals is 1.7 degrees after 8 iterations, 1.5 after 16, 1.45 after 32.
   */
  vtkSetMacro(NumberOfIterations, int);
  vtkGetMacro(NumberOfIterations, int);
  ///@}

  ///@{
  /**
   * Conjugate gradients' relative residual in each iteration's solve (in
   * (0, 1), default 1e-3; the last iteration solves to a hundredth of it).
   * The next iteration moves the targets anyway, so each solve need not be
   * exact; pieces and one process agree to about this tolerance in voxels
   * (1e-8 gives positions within 1e-6 voxel of one process's).
   */
  vtkSetMacro(SolverTolerance, double);
  vtkGetMacro(SolverTolerance, double);
  ///@}

  ///@{
  /**
   * Triangles instead of quads (default off).
   */
  vtkSetMacro(OutputTriangles, bool);
  vtkGetMacro(OutputTriangles, bool);
  vtkBooleanMacro(OutputTriangles, bool);
  ///@}

  ///@{
  /**
   * Repeat the vertices of the creases once per side (per fan of faces
   * around the vertex between two creases), each with its side's normal
   * (default on); where two sheets of voxels touch along an edge, each
   * sheet gets its own copy too. Off: one point per vertex (a watertight
   * mesh for tools that need shared points), normals averaged over all
   * faces around it.
   */
  vtkSetMacro(SplitFeaturePoints, bool);
  vtkGetMacro(SplitFeaturePoints, bool);
  vtkBooleanMacro(SplitFeaturePoints, bool);
  ///@}

  ///@{
  /**
   * The last execution's figures: crease edges, coordinates at their
   * cell's bound, the largest displacement (voxels, along an axis), and
   * whether the last solve converged.
   */
  vtkGetMacro(NumberOfCreaseEdges, vtkIdType);
  vtkGetMacro(NumberOfBoundCoordinates, vtkIdType);
  vtkGetMacro(MaximumDisplacement, double);
  vtkGetMacro(Converged, bool);
  ///@}

protected:
  vtkPiecewiseSmoothMeshFilter();
  ~vtkPiecewiseSmoothMeshFilter() override;

  vtkMTimeType GetMTime() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double DataWeight = 0.05;
  double CreaseWeight = 1.0;
  int NumberOfIterations = 16;
  double SolverTolerance = 1e-3;
  bool OutputTriangles = false;
  bool SplitFeaturePoints = true;

  vtkIdType NumberOfCreaseEdges = 0, NumberOfBoundCoordinates = 0;
  double MaximumDisplacement = 0;
  bool Converged = true;

private:
  vtkPiecewiseSmoothMeshFilter(const vtkPiecewiseSmoothMeshFilter&) = delete;
  void operator=(const vtkPiecewiseSmoothMeshFilter&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
