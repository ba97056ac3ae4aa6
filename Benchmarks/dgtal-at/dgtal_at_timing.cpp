// Single-threaded timing of DGtal's Ambrosio-Tortorelli (AT) normal regularisation
// (same pipeline as DGtal examples/dec/exampleSurfaceATNormals.cpp and
//  ShortcutsGeometry::getATVectorFieldApproximation).
//
// usage: dgtal_at_timing <file.vol> [--shortcut]   (build: CMakeLists.txt here)
//   default   : builds calculus + ATSolver2D and runs exactly the loop of
//               ATSolver2D::solveGammaConvergence/solveForEpsilon, counting iterations.
//   --shortcut: calls SHG3::getATVectorFieldApproximation( surface, surfels, ii, params )
//               (no iteration counts available; same computation).
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <vector>
#include "DGtal/base/Common.h"
#include "DGtal/helpers/StdDefs.h"
#include "DGtal/helpers/Shortcuts.h"
#include "DGtal/helpers/ShortcutsGeometry.h"
#include "DGtal/dec/ATSolver2D.h"
#include "DGtal/dec/DiscreteExteriorCalculusFactory.h"

using namespace DGtal;
typedef Z3i::KSpace                 KSpace;
typedef Shortcuts< KSpace >         SH3;
typedef ShortcutsGeometry< KSpace > SHG3;
typedef std::chrono::steady_clock   SClock;

static double secs( SClock::time_point a, SClock::time_point b )
{ return std::chrono::duration<double>( b - a ).count(); }

int main( int argc, char** argv )
{
  if ( argc < 2 ) { std::cerr << "usage: " << argv[0] << " file.vol [--shortcut]\n"; return 1; }
  const std::string volfile = argv[ 1 ];
  const bool shortcut = ( argc > 2 && std::strcmp( argv[ 2 ], "--shortcut" ) == 0 );

  // ---- parameters (DGtal names) ----
  auto params = SH3::defaultParameters() | SHG3::defaultParameters()
              | SHG3::parametersATApproximation();
  params( "verbose",          0 )
        ( "thresholdMin",     0 )     // inside: value > 0
        ( "thresholdMax",   255 )     //         value <= 255
        ( "gridstep",       1.0 )
        ( "r-radius",       3.0 )     // II radius (grid units; alpha irrelevant at h=1)
        ( "at-alpha",       0.1 )
        ( "at-lambda",      0.01 )
        ( "at-epsilon-start", 2.0 )
        ( "at-epsilon",     0.25 )    // last epsilon
        ( "at-epsilon-ratio", 2.0 )
        ( "at-max-iter",    10 )
        ( "at-diff-v-max",  1e-4 );   // (ATSolver2D hard-codes 1e-4 anyway)
  const double alpha_at  = params[ "at-alpha"         ].as<double>();
  const double lambda_at = params[ "at-lambda"        ].as<double>();
  const double eps1      = params[ "at-epsilon-start" ].as<double>();
  const double eps2      = params[ "at-epsilon"       ].as<double>();
  const double epsr      = params[ "at-epsilon-ratio" ].as<double>();
  const int    max_iter  = params[ "at-max-iter"      ].as<int>();
  const double tol       = params[ "at-diff-v-max"    ].as<double>();

  // ---- load volume ----
  auto t0 = SClock::now();
  auto bimage  = SH3::makeBinaryImage( volfile, params );
  auto t1 = SClock::now();
  // ---- digital surface + II normals ----
  auto K       = SH3::getKSpace( bimage, params );
  auto surface = SH3::makeDigitalSurface( bimage, K, params );
  auto surfels = SH3::getSurfelRange( surface, params );
  auto t2 = SClock::now();
  auto ii_normals = SHG3::getIINormalVectors( bimage, surfels, params );
  auto t3 = SClock::now();

  std::cout << "file              " << volfile << "\n";
  std::cout << "surfels           " << surfels.size() << "\n";
  std::cout << std::fixed << std::setprecision( 3 );
  std::cout << "t_load_vol        " << secs( t0, t1 ) << " s\n";
  std::cout << "t_surface         " << secs( t1, t2 ) << " s\n";
  std::cout << "t_II_normals(r=3) " << secs( t2, t3 ) << " s\n";
  std::cout << "t_surface+II      " << secs( t1, t3 ) << " s\n";

  SH3::RealVectors at_normals;
  std::vector<int> iters;
  std::vector<double> last_dv;
  SClock::time_point a0, a1, a2, a3, a4;
  if ( shortcut )
    {
      a0 = SClock::now();
      at_normals = SHG3::getATVectorFieldApproximation( surface, surfels, ii_normals, params );
      a4 = SClock::now();
      std::cout << "mode              shortcut (SHG3::getATVectorFieldApproximation)\n";
    }
  else
    {
      typedef DiscreteExteriorCalculusFactory<EigenLinearAlgebraBackend> CalculusFactory;
      a0 = SClock::now();
      const auto calculus = CalculusFactory::createFromNSCells<2>( surfels.cbegin(), surfels.cend() );
      a1 = SClock::now();
      ATSolver2D< KSpace > at_solver( calculus, 0 );
      at_solver.initInputVectorFieldU2( ii_normals, surfels.cbegin(), surfels.cend() );
      at_solver.setUp( alpha_at, lambda_at );
      a2 = SClock::now();
      // == ATSolver2D::solveGammaConvergence( eps1, eps2, epsr, false, tol, max_iter )
      for ( double eps = eps1; eps >= eps2; eps /= epsr )
        { // == ATSolver2D::solveForEpsilon( eps, tol, max_iter )
          at_solver.setEpsilon( eps );
          int n = 0; double dv = 0.0;
          for ( int i = 0; i < max_iter; ++i )
            {
              at_solver.solveOneAlternateStep();
              ++n;
              dv = std::get<0>( at_solver.diffV0() );
              if ( dv < tol ) break;
            }
          iters.push_back( n ); last_dv.push_back( dv );
        }
      a3 = SClock::now();
      at_normals = ii_normals;
      at_solver.getOutputVectorFieldU2( at_normals, surfels.cbegin(), surfels.cend() );
      a4 = SClock::now();
      std::cout << "mode              explicit (calculus + ATSolver2D, solveGammaConvergence loop)\n";
      std::cout << "t_AT_calculus     " << secs( a0, a1 ) << " s\n";
      std::cout << "t_AT_init+setUp   " << secs( a1, a2 ) << " s\n";
      std::cout << "t_AT_solve        " << secs( a2, a3 ) << " s\n";
      std::cout << "t_AT_output       " << secs( a3, a4 ) << " s\n";
    }
  std::cout << "t_AT_total        " << secs( a0, a4 ) << " s\n";
  if ( ! iters.empty() )
    {
      int tot = 0;
      std::cout << "AT iterations     ";
      double eps = eps1;
      for ( size_t k = 0; k < iters.size(); ++k, eps /= epsr )
        {
          std::cout << "eps=" << std::setprecision( 2 ) << eps << ":" << iters[ k ]
                    << "(|dv|oo=" << std::scientific << std::setprecision( 2 ) << last_dv[ k ]
                    << std::fixed << ") ";
          tot += iters[ k ];
        }
      std::cout << " total=" << tot << "\n";
    }
  // checksum / sanity: mean angle between II and AT normals (AT u is not renormalised)
  double sum_ang = 0.0, chk = 0.0;
  for ( size_t i = 0; i < surfels.size(); ++i )
    {
      auto u = at_normals[ i ]; const double nu = u.norm();
      if ( nu > 0 ) u /= nu;
      double c = std::max( -1.0, std::min( 1.0, u.dot( ii_normals[ i ] ) ) );
      sum_ang += std::acos( c );
      chk += at_normals[ i ][ 0 ] + 2.0 * at_normals[ i ][ 1 ] + 3.0 * at_normals[ i ][ 2 ];
    }
  std::cout << std::setprecision( 6 );
  std::cout << "mean_angle(II,AT) " << ( sum_ang / surfels.size() ) * 180.0 / M_PI << " deg\n";
  std::cout << "checksum          " << std::setprecision( 9 ) << chk << "\n";
  return 0;
}
