/**
 * @class   vtkSharpFeaturesFilter
 * @brief   One feature line per sharp edge, on the edge, and the normal of
 *          its own side on every face up to it: a stage after
 *          vtkAmbrosioTortorelliFilter.
 *
 * Ambrosio-Tortorelli (AT) marks each sharp edge with a band of low v a few
 * faces wide: its feature edges come out as a ladder (two lines either side
 * of the edge, rungs between them), and the faces inside the band keep the
 * input estimator's normal, blended across the edge. This filter reads the
 * band as "a discontinuity lies in here" and places it from the smooth parts
 * on either side (dgSharpFeatures.h; docs/sharp-features.md has the
 * measurements):
 * - the faces outside the band form regions (connected components; regions
 *   with fewer than MinimumRegionSize faces, such as the inside of AT's
 *   loops around noise bumps, join the band);
 * - every band face joins the nearby region whose local plane (centroid and
 *   mean normal of the region's faces found within SearchDepth face steps;
 *   for a region flat within PlanarRegionAngle, the plane through all its
 *   faces; with QuadricSides, for another large region, the quadric through
 *   all its faces) puts its outside voxel outside, and takes that side's
 *   normal;
 * - regions whose common boundary has a mean normal jump below
 *   MinimumFeatureAngle (degrees) are merged, weakest first, never joining
 *   the two sides of a boundary of StrongFeatureAngle or more; then those
 *   below StrongFeatureAngle whose smaller side lies on the larger side's
 *   quadric (QuadricMergeFactor);
 * - every line left between two merged regions is tested: a crease keeps
 *   its line, a bend (a fillet, a tube, AT's terraces on a curved part)
 *   merges its sides. The input estimator's normals (IINormals,
 *   VCMNormals or RHTNormals, or InputNormalsName), fitted on each side
 *   beyond 0.75 InputRadius from the line and extrapolated to it, must jump
 *   by MinimumFeatureAngle more than the sides' own curvature and the
 *   fits' noise explain, the band's voxels must reach the corner the two
 *   sides make (within CornerDepth), and the voxel faces must turn at the
 *   line rather than across the width of a fillet (MinimumTurnShare). Each
 *   stretch of a line is judged too (the line's edges within the fit
 *   window's reach): on a crease's line a stretch whose voxels cut the
 *   corner is not drawn, and a bend's line keeps its sides apart where a
 *   stretch is clearly a crease (a sharp edge that ends in fillets);
 * - the feature lines are the edges between faces of different regions,
 *   but for the stretches found to be bends (FeatureRegion still changes
 *   there; CreaseSides marks the drawn edges on the faces);
 * - the output normals are a twiced Gaussian mean of the input normals
 *   (the side normals within SearchDepth of a line; away from the lines
 *   and AT's band, the input blended with AT's normals as much as the
 *   surface is noisy) over the faces on the same side of every kept line,
 *   as wide as the noise the surface shows calls for (FieldWidth); on a
 *   clean surface they first undo the input's own blur (UndoInputBlur).
 *
 * Input: a vtkPolyData with polygons, a cell normal field (array 0 of
 * SetInputArrayToProcess, default "ATNormals") and a point feature indicator
 * (array 1, default "ATFeatureIndicator"): vtkAmbrosioTortorelliFilter's
 * output port 0. Any other pair of arrays with the same meaning works.
 *
 * Output port 0: the input surface (shallow copy) plus cell data
 * "SharpNormals" (unit, the active normals), "FeatureRegion" (int: the
 * smooth part each face belongs to, -1 for band faces that met no region)
 * and "CreaseSides" (unsigned char: bit i set when the face's side from
 * corner i to corner i + 1 is a feature edge; the creases that
 * vtkPiecewiseSmoothMeshFilter and vtkCorrectedCurvatureFilter keep).
 * Output port 1: the feature lines, as line cells on the surface's points,
 * with cell data "FeatureAngle" (degrees, the normal jump across the edge).
 *
 * Parameters are in grid units (face steps), like AT's. Bad input (no
 * polygons, missing or wrongly sized arrays, bad parameters) gives an error
 * and empty outputs; aborting gives empty outputs without an error.
 *
 * Pieces: the region growing and merging are global (a region can span
 * the whole surface). Under a multi-process controller every process
 * sends its own faces (matched by their cell and point "GlobalIds") to
 * process 0, which runs the stage on the whole surface in one process's
 * order and sends each process the arrays of its own faces and the feature
 * lines it owns: the result is one process's. Process 0 holds the whole
 * surface meanwhile (docs/distributed.md).
 */
#ifndef vtkSharpFeaturesFilter_h
#define vtkSharpFeaturesFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>
#include <string>

class vtkMultiProcessController;

class VTKDIGITALGEOMETRY_EXPORT vtkSharpFeaturesFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkSharpFeaturesFilter* New();
  vtkTypeMacro(vtkSharpFeaturesFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * A face is in the band when one of its points has a feature indicator
   * below this value (in (0, 1), default 0.5, AT's own FeatureThreshold).
   */
  vtkSetMacro(FeatureThreshold, double);
  vtkGetMacro(FeatureThreshold, double);
  ///@}

  ///@{
  /**
   * Regions of fewer faces join the band (>= 1, default 30): AT draws a
   * closed loop around each noise bump, whose inside is a tiny region.
   */
  vtkSetMacro(MinimumRegionSize, int);
  vtkGetMacro(MinimumRegionSize, int);
  ///@}

  ///@{
  /**
   * How far, in face steps, a band face looks past the first region face it
   * meets (>= 0, default 5): the local planes are fitted to the region faces
   * found that far.
   */
  vtkSetMacro(SearchDepth, int);
  vtkGetMacro(SearchDepth, int);
  ///@}

  ///@{
  /**
   * Majority votes over the band faces' sides (SmoothingPasses >= 0,
   * default 2), each face taking the side most faces within SmoothingDepth
   * face steps (>= 1, default 2) are on: noise moves single faces to the
   * wrong side, which would draw a wiggling line.
   */
  vtkSetMacro(SmoothingPasses, int);
  vtkGetMacro(SmoothingPasses, int);
  vtkSetMacro(SmoothingDepth, int);
  vtkGetMacro(SmoothingDepth, int);
  ///@}

  ///@{
  /**
   * At the end every face takes the mean normal of its own region's faces
   * within this many face steps (>= 0, default 3; 0 = none): a mean that
   * never reaches across a feature line, which removes most of the noise
   * AT's data term keeps on noisy volumes.
   */
  vtkSetMacro(NormalSmoothingDepth, int);
  vtkGetMacro(NormalSmoothingDepth, int);
  ///@}

  ///@{
  /**
   * The local planes' normals: fitted to the region faces' centres (least
   * squares, default on), or the mean of their input normals (off), which
   * near the band still carry the input estimator's blend across the edge.
   */
  vtkSetMacro(FitPlanes, bool);
  vtkGetMacro(FitPlanes, bool);
  vtkBooleanMacro(FitPlanes, bool);
  ///@}

  ///@{
  /**
   * A fit is used only when its RMS residual is below FitResidual edge
   * lengths (>= 0, default 0.3; a noise-free turned digital plane:
   * 0.16-0.25): on noisy surfaces the positions are too rough and the mean
   * normal is kept. The same bound says when a side is a quadric
   * (QuadricSides).
   */
  vtkSetMacro(FitResidual, double);
  vtkGetMacro(FitResidual, double);
  ///@}

  ///@{
  /**
   * Whether a band face's choice of side lets each side's plane bend by the
   * curvature that side's normals show along the edge (default on; shrunk
   * to none when not significant against the normals' scatter). Off, flat
   * planes: on a curved side the plane lies above the surface near the
   * edge and hands that side's faces to its neighbour
   * (docs/sharp-features.md).
   */
  vtkSetMacro(CurvedSides, bool);
  vtkGetMacro(CurvedSides, bool);
  vtkBooleanMacro(CurvedSides, bool);
  ///@}

  ///@{
  /**
   * How fast a growing region's reference normal follows its faces (in
   * (0, 1], default 0.2): see RegionEdgeAngle.
   */
  vtkSetMacro(ReferenceWeight, double);
  vtkGetMacro(ReferenceWeight, double);
  ///@}


  ///@{
  /**
   * Boundaries between regions with a mean normal jump below this angle
   * (degrees, >= 0, default 15) are not features: the regions merge.
   */
  vtkSetMacro(MinimumFeatureAngle, double);
  vtkGetMacro(MinimumFeatureAngle, double);
  ///@}

  ///@{
  /**
   * Boundaries whose jump is at least this angle (degrees, in [0, 180],
   * default 30; values below MinimumFeatureAngle count as it) are sure
   * features: the weak boundaries merge weakest first, and a merge that
   * would join the two sides of a sure feature through other regions is
   * refused. Under heavy noise AT's bands cut slivers off smooth parts, and
   * a sliver that meets both sides of an edge along weak boundaries would
   * otherwise erase the edge. 180 leaves every weak boundary merged.
   */
  vtkSetMacro(StrongFeatureAngle, double);
  vtkGetMacro(StrongFeatureAngle, double);
  ///@}

  ///@{
  /**
   * A smooth region whose normal field turns by less than this angle across
   * it (degrees, in [0, 90], default 6; 0: never) is a plane: its band
   * faces choose their side against the plane fitted to all the region's
   * faces, not to the few near them, which a staircase or noise tilts.
   * AT's normals lean towards the other side next to the band, so true
   * planes measure a few degrees; curved parts that small are flat enough
   * for the choice of side.
   */
  vtkSetMacro(PlanarRegionAngle, double);
  vtkGetMacro(PlanarRegionAngle, double);
  ///@}

  /// Regions found planar (PlanarRegionAngle) in the last execution.
  vtkGetMacro(NumberOfPlanarRegions, int);

  ///@{
  /**
   * Curved regions that reach beyond three band-face searches (a face more
   * than 3 SearchDepth edge lengths from their centroid) and are not planar
   * take part in the choice of side with the quadric fitted to all their
   * faces (positions and normals), wherever that quadric passes within an
   * edge length of the region's faces near the band face; elsewhere, and
   * for smaller regions, the local plane bent by CurvedSides decides. On a
   * sphere or a cylinder the whole-region quadric is not tilted by the
   * staircase and the noise that a few faces near the edge show. Once the
   * lines are known, a side (as large) whose faces lie within FitResidual
   * edge lengths (RMS) of its own quadric gives that quadric's normal to
   * its faces near a line that lie on it, as the output field's data: AT's
   * normals there are flatter than the surface. Default on.
   */
  vtkSetMacro(QuadricSides, bool);
  vtkGetMacro(QuadricSides, bool);
  vtkBooleanMacro(QuadricSides, bool);
  ///@}

  /// Regions given a quadric (QuadricSides) in the last execution.
  vtkGetMacro(NumberOfQuadricRegions, int);

  ///@{
  /**
   * A boundary whose jump lies between MinimumFeatureAngle and
   * StrongFeatureAngle merges all the same when everything already merged
   * with its smaller side lies on the quadric fitted to everything already
   * merged with its larger side (a QuadricSides region): the RMS distance
   * of those faces to the quadric is at most this factor times the larger
   * side's own (or a quarter edge length, if larger), and at most
   * QuadricMergeDistance. Under noise AT flattens patches of a curved
   * surface into facets whose normals jump at their rim; their faces
   * still lie on the curved surface, where a true facet's do not (a cap
   * cut off a sphere of radius 20 by 28 degrees lies 1.35 units off it).
   * The merged side's faces take the quadric's normal, where it is within
   * StrongFeatureAngle of theirs.
   * Default 3; 0 never merges on this ground. The price: on a clean
   * surface a true facet whose rim turns by about 20 degrees or less on a
   * sphere of radius 20 voxels or less lies within 3 quarter edges of the
   * sphere and merges too (under noise, on larger spheres as well).
   */
  vtkSetMacro(QuadricMergeFactor, double);
  vtkGetMacro(QuadricMergeFactor, double);
  ///@}

  ///@{
  /**
   * The quadric merges' ceiling (edge lengths, RMS): however rough the
   * larger side's own faces, a side farther than this from its quadric is
   * not on it (under heavy noise a sphere's own RMS reaches 2 edge
   * lengths, and a whole disc 4.5 off it would merge). Default 3.
   */
  vtkSetMacro(QuadricMergeDistance, double);
  vtkGetMacro(QuadricMergeDistance, double);
  ///@}

  /// Medium boundaries merged on the quadric test in the last execution.
  vtkGetMacro(NumberOfQuadricMerges, int);

  ///@{
  /**
   * A region does not grow across an edge whose two faces' normals differ
   * by more than this angle (degrees, > 0, default 10): where AT's band has a
   * gap, the normal still turns over a few faces, and the two sides stay
   * apart.
   */
  vtkSetMacro(RegionEdgeAngle, double);
  vtkGetMacro(RegionEdgeAngle, double);
  ///@}

  ///@{
  /**
   * The cell array of the input estimator's normals, which the crease test
   * and the output field read. Default "" (automatic): IINormals, else
   * VCMNormals, else RHTNormals (vtkAmbrosioTortorelliFilter passes its
   * input's arrays on). A name that is not on the input is an error;
   * without any, a warning, and the stage reads the regularised normals
   * instead and solves no output field.
   */
  void SetInputNormalsName(const std::string& name)
  {
    if (name != this->InputNormalsName)
    {
      this->InputNormalsName = name;
      this->Modified();
    }
  }
  void SetInputNormalsName(const char* name) { this->SetInputNormalsName(std::string(name ? name : "")); }
  const char* GetInputNormalsName() const { return this->InputNormalsName.c_str(); }
  ///@}

  ///@{
  /**
   * How far the input normals blur a crease (grid units, > 0): the
   * estimator's radius (vtkIINormalEstimator's Radius; the program sets it
   * from its estimator). The crease test fits each side's input normals
   * between 0.75 and 0.75 InputRadius + 5 edge lengths from the line.
   * Default 4, II's default.
   */
  vtkSetMacro(InputRadius, double);
  vtkGetMacro(InputRadius, double);
  ///@}

  ///@{
  /**
   * A line whose band faces lie deeper than this inside the corner its two
   * sides make (edge lengths, > 0, default 0.6) is a bend: the voxels of a
   * fillet cut the corner off by 0.29 R at 90 degrees (1.2 edges at R = 4),
   * those of a crease reach it (medians -0.2 to 0.3, clean and at the
   * paper's noise k = 0.3).
   */
  vtkSetMacro(CornerDepth, double);
  vtkGetMacro(CornerDepth, double);
  ///@}

  ///@{
  /**
   * A crease turns at its line, a bend all along its width. Each side's
   * faces are summed as area vectors (a noise bump's faces add up to its
   * rim) within 2.5 edge lengths of the line and 4.5-9.5 edge lengths out;
   * a line whose sides meet near it at less than this share of their angle
   * farther out is a bend ([0, 1], default 0.5; 0: off). A bend of radius R
   * turns by about 3 / R radians between the two near sums, so a 90-degree
   * fillet reads as a bend from R = 4 edges on; a crease whose sides curve
   * (radius R) keeps its line while its angle exceeds about 8 / R radians.
   * Measured: 0.62 or more on the creases of cubes, octahedra and
   * cube-sphere intersections (clean and noisy), 0.36-0.55 on fillets of
   * radius 6-10.
   */
  vtkSetMacro(MinimumTurnShare, double);
  vtkGetMacro(MinimumTurnShare, double);
  ///@}

  ///@{
  /**
   * The output field's width: the standard deviation, in edge lengths, of
   * the Gaussian that averages the input normals within each side of the
   * kept lines (twiced, cut at 2.5 widths). Default 0: from the noise the
   * surface shows, the share s of faces turned more than 90 degrees from
   * their input normal (0 clean, 0.22 at the paper's k = 0.3): width =
   * max(2, 1 + 1.5 min(1.5, s / 0.22)), 2 on a clean surface, 2.5 at k =
   * 0.3 (max(1, ...) with UndoInputBlur off). > 0: that width (at most
   * 20). < 0: no field (the side and region normals as they are).
   */
  vtkSetMacro(FieldWidth, double);
  vtkGetMacro(FieldWidth, double);
  ///@}

  ///@{
  /**
   * Whether the output field's data undo the input's own blur first
   * (default on). The input estimator averages the surface's normals over
   * its ball, which leans them towards the more curved side wherever the
   * curvature changes (where a fillet meets a plane, II with radius 4 is
   * 4-6 degrees off). Away from the lines, each datum d becomes d + c,
   * c = d - G d, G a Gaussian of sqrt((0.375 InputRadius)^2 + 1.75) edge
   * lengths (2 for radius 4) over the faces on its side. Under noise c is
   * mostly the noise's own, so a share a = 1 - (1 - min(1, s / 0.22))^2 of
   * it (s the noise share: a = 0 on a clean surface, 1 from the paper's
   * k = 0.3) is replaced by its average over three passes of the field's
   * Gaussian. The step acts only where its correction, averaged over the
   * field's Gaussian, exceeds 0.89 degrees (in full from 1.78; for radius
   * r these scale by 4 / r and by G's variance over (0.375 r)^2, and rise
   * by half at a = 1): a
   * systematic lean, not the digitisation's wiggle. Where that average,
   * averaged again, stays under 0.71 degrees (an evenly curved part; the
   * same scale) the field is 1.4 times as wide (its twicing with the
   * Gaussian applied twice), blended into the narrower up to 1.42 degrees.
   * Off: neither.
   */
  vtkSetMacro(UndoInputBlur, bool);
  vtkGetMacro(UndoInputBlur, bool);
  vtkBooleanMacro(UndoInputBlur, bool);
  ///@}

  /// Lines the crease test kept and merged, the noise share and the field
  /// width (edge lengths) the last execution used (0: no field).
  vtkGetMacro(NumberOfCreases, int);
  vtkGetMacro(NumberOfBends, int);
  vtkGetMacro(NoiseShare, double);
  vtkGetMacro(UsedFieldWidth, double);

  /// Wall time (seconds) of the last execution's crease test and output
  /// field solve, the two parts issue 39 added (benchmarks report their cost).
  vtkGetMacro(CreaseTestTime, double);
  vtkGetMacro(FieldTime, double);

  /**
   * What this process exchanged in the last execution over pieces (0 in
   * one process): payload bytes sent plus received, and communication calls
   * (a point-to-point message or a collective call, each counted once).
   * Process 0 gathers the surface and sends the results back, so its
   * figures are the stage's bottleneck (docs/distributed.md).
   */
  vtkGetMacro(ExchangedBytes, double);
  vtkGetMacro(ExchangedMessages, vtkIdType);

  /**
   * Figures of the last execution: band faces, band faces that met no
   * region (they keep their input normal), regions after merging.
   */
  vtkGetMacro(NumberOfBandFaces, vtkIdType);
  vtkGetMacro(NumberOfUnassignedFaces, vtkIdType);
  vtkGetMacro(NumberOfRegions, int);

  vtkMTimeType GetMTime() override;

protected:
  vtkSharpFeaturesFilter();
  ~vtkSharpFeaturesFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// The stage on one whole surface: 1 done, 0 failed (error reported), -1
  /// aborted.
  int Execute(vtkPolyData* input, vtkPolyData* output, vtkPolyData* lines);
  /// Pieces: the surface gathered on process 0 in one process's order, the
  /// stage run there, each process's faces and lines sent back
  /// (vtkSharpFeaturesFilterPieces.cxx).
  int RequestDataPieces(vtkMultiProcessController* controller, vtkPolyData* input,
    vtkPolyData* output, vtkPolyData* lines);

  double FeatureThreshold = 0.5;
  int MinimumRegionSize = 30;
  int SearchDepth = 5;
  int SmoothingPasses = 2;
  int SmoothingDepth = 2;
  bool FitPlanes = true;
  bool CurvedSides = true;
  int NormalSmoothingDepth = 3;
  double FitResidual = 0.3;
  double ReferenceWeight = 0.2;
  double MinimumFeatureAngle = 15.0;
  double StrongFeatureAngle = 30.0;
  double PlanarRegionAngle = 6.0;
  int NumberOfPlanarRegions = 0;
  bool QuadricSides = true;
  int NumberOfQuadricRegions = 0;
  double QuadricMergeFactor = 3.0;
  double QuadricMergeDistance = 3.0;
  int NumberOfQuadricMerges = 0;
  double RegionEdgeAngle = 10.0;
  std::string InputNormalsName;
  double InputRadius = 4.0;
  double CornerDepth = 0.6;
  double MinimumTurnShare = 0.5;
  double FieldWidth = 0.0;
  bool UndoInputBlur = true;
  int NumberOfCreases = 0;
  double CreaseTestTime = 0;
  double FieldTime = 0;
  double ExchangedBytes = 0;
  vtkIdType ExchangedMessages = 0;
  int NumberOfBends = 0;
  double NoiseShare = 0.0;
  double UsedFieldWidth = 0.0;
  vtkIdType NumberOfBandFaces = 0;
  vtkIdType NumberOfUnassignedFaces = 0;
  int NumberOfRegions = 0;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;

  vtkSharpFeaturesFilter(const vtkSharpFeaturesFilter&) = delete;
  void operator=(const vtkSharpFeaturesFilter&) = delete;
};

#endif
