// DGtal's DigitalSurfaceRegularization (Coeurjolly et al., DGCI 2017) fed the
// normals of this module's program, to set beside vtkPiecewiseSmoothMeshFilter.
//
// usage: dgtal_regularization OUT.vol OUT.txt [--obj mesh.obj] [--runs 3] [--verbose]
//   OUT.vol, OUT.txt: written by export_normals.py from the program's surface
//   (the volume whose boundary the surface is, and "i j k dir nx ny nz" per surfel).
//   --verbose: DGtal prints each step of its descent.
// Prints the time of DigitalSurfaceRegularization::regularize alone (median of
// --runs, each from the digital surface: reset() in between), of init() (its
// caches) and the peak memory; writes the regularized quads in the .txt's
// surfel order (so face f is the program's cell f) as an OBJ in voxel units of
// the program's input (InsideVoxel indices: voxel centres at integers).
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <unordered_map>
#include <vector>
#include "DGtal/base/Common.h"
#include "DGtal/helpers/StdDefs.h"
#include "DGtal/helpers/Shortcuts.h"
#include "DGtal/helpers/ShortcutsGeometry.h"
#include "DGtal/geometry/surfaces/DigitalSurfaceRegularization.h"

using namespace DGtal;
typedef Z3i::KSpace               KSpace;
typedef Shortcuts< KSpace >       SH3;
typedef ShortcutsGeometry< KSpace > SHG3;
typedef std::chrono::steady_clock SClock;

static double secs( SClock::time_point a, SClock::time_point b )
{ return std::chrono::duration<double>( b - a ).count(); }

// kB from /proc/self/status ("VmHWM" peak resident, "VmRSS" current)
static long procStatus( const char* key )
{
  std::ifstream in( "/proc/self/status" );
  std::string line;
  while ( std::getline( in, line ) )
    if ( line.rfind( key, 0 ) == 0 ) return std::atol( line.c_str() + std::strlen( key ) + 1 );
  return -1;
}

// Writing 5 to clear_refs resets VmHWM, so the peak of the regularization
// alone can be read after it (Linux >= 4.0).
static void resetPeak() { std::ofstream( "/proc/self/clear_refs" ) << "5"; }

struct Surfel { long i, j, k; int dir; SH3::RealVector n; };

struct Options { std::string objfile; int runs = 3; bool verbose = false; };

// The program's surfels (export_normals.py's .txt), found by inside voxel and
// direction (0..5: -x,+x,-y,+y,-z,+z).
struct Input
{
  std::vector< Surfel > surfels; // in the .vtp's cell order
  long offset[ 3 ] = { 0, 0, 0 }; // .txt voxel indices + offset = InsideVoxel
  std::unordered_map< uint64_t, size_t > index;
  Z3i::Point ext;
  uint64_t key( long i, long j, long k, int dir ) const
  { return ( ( uint64_t( k ) * ext[ 1 ] + j ) * ext[ 0 ] + i ) * 6 + dir; }
};

typedef DigitalSurfaceRegularization< SH3::DigitalSurface > Regularization;
int run( CountedPtr< SH3::DigitalSurface > surface, const KSpace& K, CountedPtr< SH3::BinaryImage > bimage,
         Input& input, const Options& opt, SClock::time_point t0 );

int main( int argc, char** argv )
{
  if ( argc < 3 )
    {
      std::cerr << "usage: " << argv[ 0 ] << " OUT.vol OUT.txt [--obj mesh.obj] [--runs 3] [--verbose]\n";
      return 1;
    }
  Options opt;
  for ( int a = 3; a < argc; ++a )
    {
      if ( !std::strcmp( argv[ a ], "--obj" ) && a + 1 < argc ) opt.objfile = argv[ ++a ];
      else if ( !std::strcmp( argv[ a ], "--runs" ) && a + 1 < argc ) opt.runs = std::max( 1, std::atoi( argv[ ++a ] ) );
      else if ( !std::strcmp( argv[ a ], "--verbose" ) ) opt.verbose = true;
    }

  // ---- the program's surfels and normals (export_normals.py) ----
  Input input;
  std::ifstream txt( argv[ 2 ] );
  std::string header;
  std::getline( txt, header );
  size_t nsurfels = 0;
  // (sscanf: DGtal's image-writing operator>> makes "stream >> std::string" ambiguous)
  if ( std::sscanf( header.c_str(), "# surfels %zu offset %ld %ld %ld", &nsurfels,
                    &input.offset[ 0 ], &input.offset[ 1 ], &input.offset[ 2 ] ) != 4 )
    { std::cerr << "bad header in " << argv[ 2 ] << "\n"; return 1; }
  input.surfels.resize( nsurfels );
  for ( auto& s : input.surfels )
    txt >> s.i >> s.j >> s.k >> s.dir >> s.n[ 0 ] >> s.n[ 1 ] >> s.n[ 2 ];
  if ( !txt ) { std::cerr << "cannot read " << argv[ 2 ] << "\n"; return 1; }

  // ---- DGtal's digital surface of the volume, as the Shortcuts build it ----
  auto params = SH3::defaultParameters() | SHG3::defaultParameters();
  params( "thresholdMin", 0 )( "thresholdMax", 255 ); // inside: 0 < value <= 255
  auto t0 = SClock::now();
  auto bimage  = SH3::makeBinaryImage( argv[ 1 ], params );
  auto K       = SH3::getKSpace( bimage, params );
  input.ext = K.upperBound() - K.lowerBound() + Z3i::Point::diagonal( 1 );
  input.index.reserve( nsurfels );
  for ( size_t f = 0; f < nsurfels; ++f )
    {
      const auto& s = input.surfels[ f ];
      input.index[ input.key( s.i, s.j, s.k, s.dir ) ] = f;
    }
  // The explicit surface (a std::set of surfels): every boundary surfel, as
  // in the program's surface. (The light one keeps one big component, and
  // DigitalSurfaceRegularization::cacheInit names SH3::DigitalSurface::Face,
  // so the class compiles for the explicit surface only.)
  return run( SH3::makeDigitalSurface( bimage, K, params ), K, bimage, input, opt, t0 );
}

int run( CountedPtr< SH3::DigitalSurface > surface, const KSpace& K, CountedPtr< SH3::BinaryImage > bimage,
         Input& input, const Options& opt, SClock::time_point t0 )
{
  auto t1 = SClock::now();
  const size_t nsurfels = input.surfels.size();
  if ( surface->size() != nsurfels )
    {
      std::cerr << "DGtal's surface has " << surface->size() << " surfels, the program's "
                << nsurfels << "\n";
      return 1;
    }
  // DGtal orients boundary surfels so that the direct incident spel along
  // the orthogonal direction is the inside voxel.
  auto line = [&]( const SH3::SCell& s ) -> size_t
  {
    const auto d   = K.sOrthDir( s );
    const auto in  = K.sDirectIncident( s, d );
    const auto p   = K.sCoords( in );
    const int  dir = 2 * int( d ) + ( K.sKCoords( s )[ d ] > K.sKCoords( in )[ d ] ? 1 : 0 );
    auto it = input.index.find( input.key( p[ 0 ], p[ 1 ], p[ 2 ], dir ) );
    if ( it == input.index.end() || !( *bimage )( p ) )
      {
        std::cerr << "surfel " << s << " is not one of the program's\n";
        std::exit( 1 );
      }
    return it->second;
  };

  // ---- regularization: documented defaults alpha 0.001, beta 1, gamma 0.05;
  //      200 steps, dt 1, epsilon 1e-4, each vertex clamped to the unit cube
  //      around its digital position (clampedAdvection) ----
  const long rss0 = procStatus( "VmRSS" ), peak0 = procStatus( "VmHWM" );
  resetPeak();
  auto t2 = SClock::now();
  Regularization regul( surface );
  regul.init(); // caches: pointels, the dual polygonal surface, umbrellas
  auto t3 = SClock::now();
  regul.attachNormalVectors( [&]( SH3::SCell& s ) { return input.surfels[ line( s ) ].n; } );
  auto t4 = SClock::now();
  if ( opt.verbose ) regul.enableVerbose();
  const double e0 = regul.computeGradient();
  std::vector< double > times;
  double energy = 0.0;
  for ( int r = 0; r < opt.runs; ++r )
    {
      regul.reset();
      auto a = SClock::now();
      energy = regul.regularize( 200, 1.0, 0.0001, Regularization::clampedAdvection );
      times.push_back( secs( a, SClock::now() ) );
    }
  const long peakReg = procStatus( "VmHWM" );
  std::vector< double > sorted = times;
  std::sort( sorted.begin(), sorted.end() );

  std::cout << std::fixed << std::setprecision( 3 );
  std::cout << "surfels            " << nsurfels << "\n";
  std::cout << "pointels           " << regul.getRegularizedPositions().size() << "\n";
  std::cout << "t_volume+surface   " << secs( t0, t1 ) << " s\n";
  std::cout << "t_init             " << secs( t2, t3 ) << " s\n";
  std::cout << "t_attach_normals   " << secs( t3, t4 ) << " s\n";
  std::cout << "t_regularize       ";
  for ( double t : times ) std::cout << t << " ";
  std::cout << "s, median " << sorted[ sorted.size() / 2 ] << " s\n";
  std::cout << "energy             " << e0 << " -> " << energy << "\n";
  std::cout << "rss_before_init    " << rss0 / 1024.0 << " MiB\n";
  std::cout << "peak_init+regul    " << peakReg / 1024.0 << " MiB\n";

  // ---- OBJ: the pointels moved, one quad per surfel in the .txt's order ----
  if ( !opt.objfile.empty() )
    {
      const auto& pos   = regul.getRegularizedPositions();
      const auto& orig  = regul.getOriginalPositions();
      const auto& cells = regul.getCellIndex();
      std::vector< std::array< size_t, 4 > > quads( nsurfels );
      for ( auto s : *surface )
        {
          // the umbrella of the surfel, as DigitalSurfaceRegularization walks it
          auto faces = surface->facesAroundVertex( s, true );
          std::array< size_t, 4 > q;
          for ( int j = 0; j < 4; ++j )
            q[ j ] = cells.at( K.unsigns( surface->pivot( faces[ j ] ) ) );
          // outward (from the inside voxel) like the program's polygons
          const size_t f = line( s );
          const auto n = ( orig[ q[ 2 ] ] - orig[ q[ 0 ] ] ).crossProduct( orig[ q[ 3 ] ] - orig[ q[ 1 ] ] );
          const int d = input.surfels[ f ].dir;
          if ( ( d % 2 ? 1.0 : -1.0 ) * n[ d / 2 ] < 0 ) std::swap( q[ 1 ], q[ 3 ] );
          quads[ f ] = q;
        }
      std::ofstream obj( opt.objfile );
      obj << std::setprecision( 17 );
      for ( const auto& p : pos )
        obj << "v " << p[ 0 ] + input.offset[ 0 ] << " " << p[ 1 ] + input.offset[ 1 ] << " " << p[ 2 ] + input.offset[ 2 ] << "\n";
      for ( const auto& q : quads )
        obj << "f " << q[ 0 ] + 1 << " " << q[ 1 ] + 1 << " " << q[ 2 ] + 1 << " " << q[ 3 ] + 1 << "\n";
    }
  std::cout << "peak_process       " << std::max( peak0, procStatus( "VmHWM" ) ) / 1024.0 << " MiB\n";
  return 0;
}
