/**
 * @class   vtkCorrectedCurvatureFilter
 * @brief   Mean, Gaussian and principal curvatures of a surface from a good
 *          normal field (corrected curvature measures), up to its sharp
 *          edges: a stage after vtkSharpFeaturesFilter.
 *
 * Curvature measured on voxel faces is useless (their normals take six
 * values), and integral-invariant curvatures blur every sharp edge over
 * their ball. This filter keeps the faces' positions and replaces their
 * normals by a cell normal field u (default: the active cell normals, which
 * are SharpNormals after vtkSharpFeaturesFilter): the curvature measures of
 * "the surface as u says it bends" (area mu0, mean curvature mu1, Gaussian
 * curvature mu2, the anisotropic measure for the principal directions) are
 * computed exactly per face (u interpolated linearly on the triangles
 * around each face's centre), then summed over a ball of radius Radius
 * around each face (docs/curvature-measures.md states every formula).
 *
 * Per side (PerSide, default on): with a region array (array 1 of
 * SetInputArrayToProcess, default "FeatureRegion", the sharp stage's smooth
 * parts), a face's ball and its corners' normals use only the faces of its
 * own region, so that the curvature of each side is measured up to the
 * crease and never the crease itself. The crease is reported as what it is
 * on output port 1: each edge between two regions with the angle by which
 * the normal turns across it (its mean-curvature measure, concentrated on
 * the line, is that angle times the edge's length). Without a region array
 * the surface is one region (there is no crease to keep apart). With the
 * sharp stage's "CreaseSides" as well (array 2: per face, bit i set when
 * the side from corner i to corner i + 1 is a feature edge), the creases
 * are its drawn edges only: where it left a stretch of a region boundary
 * undrawn (a sharp edge that ends in a fillet), the corner normals there
 * take the faces of both regions and no crease is reported (the sides are
 * named by the faces' corner order, as the sharp stage wrote them; bits
 * that no longer match it, an edge flagged by one of its two faces only,
 * are an error).
 *
 * Output port 0: the input (shallow copy) with cell data
 * "CorrectedMeanCurvature" (H, positive on a sphere with outward normals),
 * "CorrectedGaussianCurvature" (G), "CorrectedK1" >= "CorrectedK2" and
 * their unit directions "CorrectedK1Direction", "CorrectedK2Direction", in
 * inverse world units, and "CorrectedBallRadius" (each face's ball radius,
 * world units); and field data (one value each): "CorrectedArea",
 * "EnclosedVolume" (NaN when the surface is not closed),
 * "SpecificSurfaceArea" (area / volume), "IntegralMeanCurvature",
 * "IntegralGaussianCurvature", "GaussBonnetCharacteristic" (the integral of
 * G over 2 pi: the Euler characteristic of a closed surface, a self-check),
 * "EulerCharacteristic" (V - E + F of the faces) and
 * "CreaseIntegralMeanCurvature" (the part of the integral of H the creases
 * hold). The whole-surface figures always use one continuous field (corner
 * normals from all faces around a corner), so that creases and corners
 * count.
 * Output port 1: the crease edges (lines on the input's points) with cell
 * data "CreaseAngle" (degrees; positive where the surface is convex, as a
 * cube's edges, negative where concave). Empty without PerSide or regions.
 *
 * Bad input (no polygons, no or non-unit normals, a region array of the
 * wrong size, Radius <= 0 or larger than the surface) gives an error and
 * empty outputs.
 *
 * Pieces: under a multi-process controller, each process computes its own
 * faces (the input's non-ghost cells, matched across pieces by their cell
 * and point "GlobalIds") after receiving the other pieces' faces its balls
 * reach; the arrays, the creases (each reported once, by the process
 * owning the face of smaller global id) and the whole-surface figures are
 * those of one process, to rounding.
 */
#ifndef vtkCorrectedCurvatureFilter_h
#define vtkCorrectedCurvatureFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>

class VTKDIGITALGEOMETRY_EXPORT vtkCorrectedCurvatureFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkCorrectedCurvatureFilter* New();
  vtkTypeMacro(vtkCorrectedCurvatureFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum RadiusUnitsTypes
  {
    VOXELS = 0,
    WORLD = 1
  };

  ///@{
  /**
   * Ball radius (> 0, default 6), in RadiusUnits. Larger balls average
   * more noise away and blur more where the curvature varies. With
   * AdaptiveRadius (default) it is the first pass's ball and the scale of
   * each face's own: within [2/3, 3] Radius. Without, every ball has this
   * radius: 6 voxels gives the smallest worst error of one radius over
   * spheres, a torus, an ellipsoid and DGtal's goursat surface, clean and
   * noisy (docs/curvature-measures.md).
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

  ///@{
  /**
   * A ball radius per face (default on): after a first pass with balls of
   * Radius, each face's radius balances the noise of the measure (falling
   * with the ball) against the bias of the curvature's variation (growing
   * with it), both measured around the face, within [2/3, 3] Radius and at
   * most its smallest curvature radius; large on flat or evenly curved
   * parts, small where the curvature changes (docs/curvature-measures.md,
   * "The ball radius per face"). The radius used is the cell array
   * "CorrectedBallRadius". Off: every ball has radius Radius.
   */
  vtkSetMacro(AdaptiveRadius, bool);
  vtkGetMacro(AdaptiveRadius, bool);
  vtkBooleanMacro(AdaptiveRadius, bool);
  ///@}

  ///@{
  /**
   * Units of Radius: VOXELS (default; of the smallest spacing in the
   * input's "ImageSpacing" field data, or the faces' mean edge length
   * without it) or WORLD.
   */
  vtkSetClampMacro(RadiusUnits, int, VOXELS, WORLD);
  vtkGetMacro(RadiusUnits, int);
  void SetRadiusUnitsToVoxels() { this->SetRadiusUnits(VOXELS); }
  void SetRadiusUnitsToWorld() { this->SetRadiusUnits(WORLD); }
  ///@}

  ///@{
  /**
   * Measure each side of a crease on its own (default on): balls and corner
   * normals keep to the face's own region (array 1), and the creases are
   * reported on output port 1.
   */
  vtkSetMacro(PerSide, bool);
  vtkGetMacro(PerSide, bool);
  vtkBooleanMacro(PerSide, bool);
  ///@}

  ///@{
  /**
   * The last execution's whole-surface figures (also in the output's field
   * data) and the radius it used, in world units.
   */
  vtkGetMacro(Area, double);
  vtkGetMacro(Volume, double);
  vtkGetMacro(IntegralMeanCurvature, double);
  vtkGetMacro(IntegralGaussianCurvature, double);
  vtkGetMacro(CreaseIntegralMeanCurvature, double);
  vtkGetMacro(EulerCharacteristic, vtkIdType);
  vtkGetMacro(NumberOfCreaseEdges, vtkIdType);
  vtkGetMacro(UsedRadius, double);
  ///@}

protected:
  vtkCorrectedCurvatureFilter();
  ~vtkCorrectedCurvatureFilter() override;

  vtkMTimeType GetMTime() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Radius = 6.0;
  bool AdaptiveRadius = true;
  int RadiusUnits = VOXELS;
  bool PerSide = true;

  double Area = 0, Volume = 0, IntegralMeanCurvature = 0, IntegralGaussianCurvature = 0;
  double CreaseIntegralMeanCurvature = 0, UsedRadius = 0;
  vtkIdType EulerCharacteristic = 0, NumberOfCreaseEdges = 0;

private:
  vtkCorrectedCurvatureFilter(const vtkCorrectedCurvatureFilter&) = delete;
  void operator=(const vtkCorrectedCurvatureFilter&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
