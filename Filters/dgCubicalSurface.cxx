#include "dgCubicalSurface.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <cassert>

namespace dg
{

void PaddedMask::Allocate(int nx, int ny, int nz)
{
  this->Dims[0] = nx;
  this->Dims[1] = ny;
  this->Dims[2] = nz;
  this->Data.assign(static_cast<std::size_t>(this->RowLength()) * ny * nz, 0);
  this->RowMin.assign(static_cast<std::size_t>(ny) * nz, 1);
  this->RowMax.assign(static_cast<std::size_t>(ny) * nz, 0);
}

bool PaddedMask::Inside(int i, int j, int k) const
{
  if (i < 0 || j < 0 || k < 0 || i >= this->Dims[0] || j >= this->Dims[1] || k >= this->Dims[2])
  {
    return false;
  }
  return this->Row(j, k)[i + 1] != 0;
}

void PaddedMask::UpdateRowBounds()
{
  const int nx = this->Dims[0];
  const int ny = this->Dims[1];
  const std::int64_t rows = static_cast<std::int64_t>(ny) * this->Dims[2];
  vtkSMPTools::For(0, rows, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      const std::uint8_t* row = this->Data.data() + r * this->RowLength() + 1;
      int lo = 0;
      while (lo < nx && !row[lo])
      {
        ++lo;
      }
      int hi = nx - 1;
      while (hi > lo && !row[hi])
      {
        --hi;
      }
      if (lo == nx)
      {
        this->RowMin[r] = 1;
        this->RowMax[r] = 0;
      }
      else
      {
        this->RowMin[r] = lo;
        this->RowMax[r] = hi;
      }
    }
  });
}

namespace
{

// Corner offsets (di, dj, dk) of each surfel direction, in counter-clockwise
// order seen from outside, so that the right-hand normal points outward.
const int QuadCorners[6][4][3] = {
  { { 0, 0, 0 }, { 0, 0, 1 }, { 0, 1, 1 }, { 0, 1, 0 } }, // -x
  { { 1, 0, 0 }, { 1, 1, 0 }, { 1, 1, 1 }, { 1, 0, 1 } }, // +x
  { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 0, 1 }, { 0, 0, 1 } }, // -y
  { { 0, 1, 0 }, { 0, 1, 1 }, { 1, 1, 1 }, { 1, 1, 0 } }, // +y
  { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 1, 0, 0 } }, // -z
  { { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } }, // +z
};

class Extractor
{
public:
  Extractor(const PaddedMask& mask)
    : Mask(mask)
    , Zero(static_cast<std::size_t>(mask.RowLength()), 0)
  {
    this->NX = mask.Dims[0];
    this->NY = mask.Dims[1];
    this->NZ = mask.Dims[2];
  }

  const PaddedMask& Mask;
  std::vector<std::uint8_t> Zero;
  int NX, NY, NZ;

  // Voxel rows outside the grid read as a row of outside voxels.
  const std::uint8_t* VoxelRow(int j, int k) const
  {
    if (j < 0 || k < 0 || j >= this->NY || k >= this->NZ)
    {
      return this->Zero.data();
    }
    return this->Mask.Row(j, k);
  }
  bool RowEmpty(int j, int k) const
  {
    if (j < 0 || k < 0 || j >= this->NY || k >= this->NZ)
    {
      return true;
    }
    const std::size_t r = static_cast<std::size_t>(k) * this->NY + j;
    return this->Mask.RowMin[r] > this->Mask.RowMax[r];
  }

  // Corner rows: (NY+1) x (NZ+1), corner row (cj, ck) lies between voxel
  // rows j in {cj-1, cj}, k in {ck-1, ck}.
  std::int64_t NumberOfCornerRows() const
  {
    return static_cast<std::int64_t>(this->NY + 1) * (this->NZ + 1);
  }

  struct CornerRowScan
  {
    const std::uint8_t* Rows[4];
    int Lo, Hi; // corner index range to scan (Lo > Hi: nothing)
  };

  CornerRowScan ScanRange(int cj, int ck) const
  {
    CornerRowScan s;
    s.Lo = this->NX + 1;
    s.Hi = -1;
    int n = 0;
    for (int dk = -1; dk <= 0; ++dk)
    {
      for (int dj = -1; dj <= 0; ++dj)
      {
        const int j = cj + dj, k = ck + dk;
        s.Rows[n++] = this->VoxelRow(j, k);
        if (!this->RowEmpty(j, k))
        {
          const std::size_t r = static_cast<std::size_t>(k) * this->NY + j;
          s.Lo = std::min(s.Lo, this->Mask.RowMin[r]);
          s.Hi = std::max(s.Hi, this->Mask.RowMax[r] + 1);
        }
      }
    }
    return s;
  }

  // A corner is a pointel of the surface iff its 8 voxels are not all of the
  // same state (the 2x2x2 block is connected, so a mixed block always holds a
  // separating surfel incident to the corner). Padded index of voxel ci-1 is ci.
  static bool IsPointel(const CornerRowScan& s, int ci)
  {
    const int sum = s.Rows[0][ci] + s.Rows[0][ci + 1] + s.Rows[1][ci] + s.Rows[1][ci + 1] +
      s.Rows[2][ci] + s.Rows[2][ci + 1] + s.Rows[3][ci] + s.Rows[3][ci + 1];
    return sum != 0 && sum != 8;
  }

  // Bitmask of the surfel directions present on voxel (i, j, k), which must be inside.
  int Faces(const std::uint8_t* row, const std::uint8_t* ym, const std::uint8_t* yp,
    const std::uint8_t* zm, const std::uint8_t* zp, int i) const
  {
    const int p = i + 1;
    return (row[p - 1] ? 0 : 1) | (row[p + 1] ? 0 : 2) | (ym[p] ? 0 : 4) | (yp[p] ? 0 : 8) |
      (zm[p] ? 0 : 16) | (zp[p] ? 0 : 32);
  }
};

inline int PopCount6(int m)
{
  return (m & 1) + ((m >> 1) & 1) + ((m >> 2) & 1) + ((m >> 3) & 1) + ((m >> 4) & 1) + ((m >> 5) & 1);
}

} // namespace

bool ExtractCubicalSurface(
  const PaddedMask& mask, CubicalSurface& out, const ProgressCallback& progress)
{
  out = CubicalSurface();
  auto report = [&](double f) { return progress ? progress(f) : true; };
  if (mask.Dims[0] <= 0 || mask.Dims[1] <= 0 || mask.Dims[2] <= 0)
  {
    return true;
  }
  Extractor ex(mask);
  const int NY = ex.NY;
  const std::int64_t nCornerRows = ex.NumberOfCornerRows();
  const std::int64_t nVoxelRows = static_cast<std::int64_t>(NY) * ex.NZ;

  // Pass 1: count pointels per corner row and surfels per voxel row.
  std::vector<std::int64_t> pointOffsets(nCornerRows + 1, 0);
  std::vector<std::int64_t> surfelOffsets(nVoxelRows + 1, 0);
  vtkSMPTools::For(0, nCornerRows, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      const int cj = static_cast<int>(r % (NY + 1));
      const int ck = static_cast<int>(r / (NY + 1));
      const auto s = ex.ScanRange(cj, ck);
      std::int64_t n = 0;
      for (int ci = s.Lo; ci <= s.Hi; ++ci)
      {
        n += Extractor::IsPointel(s, ci);
      }
      pointOffsets[r] = n;
    }
  });
  vtkSMPTools::For(0, nVoxelRows, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      const int j = static_cast<int>(r % NY);
      const int k = static_cast<int>(r / NY);
      const std::uint8_t* row = mask.Row(j, k);
      const std::uint8_t *ym = ex.VoxelRow(j - 1, k), *yp = ex.VoxelRow(j + 1, k);
      const std::uint8_t *zm = ex.VoxelRow(j, k - 1), *zp = ex.VoxelRow(j, k + 1);
      std::int64_t n = 0;
      for (int i = mask.RowMin[r]; i <= mask.RowMax[r]; ++i)
      {
        if (row[i + 1])
        {
          n += PopCount6(ex.Faces(row, ym, yp, zm, zp, i));
        }
      }
      surfelOffsets[r] = n;
    }
  });
  if (!report(0.4))
  {
    return false;
  }

  // Prefix sums: each row's first output index.
  auto exclusiveScan = [](std::vector<std::int64_t>& v) {
    std::int64_t sum = 0;
    for (auto& x : v)
    {
      const std::int64_t c = x;
      x = sum;
      sum += c;
    }
    return sum;
  };
  const std::int64_t nPoints = exclusiveScan(pointOffsets);
  const std::int64_t nSurfels = exclusiveScan(surfelOffsets);
  out.Corners.resize(3 * nPoints);
  out.Quads.resize(4 * nSurfels);
  out.Voxels.resize(3 * nSurfels);
  out.Directions.resize(nSurfels);

  // Pass 2: write the pointels of every corner row, sorted by x.
  vtkSMPTools::For(0, nCornerRows, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      const int cj = static_cast<int>(r % (NY + 1));
      const int ck = static_cast<int>(r / (NY + 1));
      const auto s = ex.ScanRange(cj, ck);
      std::int32_t* c = out.Corners.data() + 3 * pointOffsets[r];
      for (int ci = s.Lo; ci <= s.Hi; ++ci)
      {
        if (Extractor::IsPointel(s, ci))
        {
          *c++ = ci;
          *c++ = cj;
          *c++ = ck;
        }
      }
    }
  });
  if (!report(0.7))
  {
    return false;
  }

  // Pass 3: write the surfels of every voxel row, looking their corners up in
  // the four neighbouring corner rows with one forward-moving cursor each.
  // The longest pass: in slabs of rows, so that progress and abort are
  // handled every 5% (rows are independent).
  auto pass3 = [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      const int j = static_cast<int>(r % NY);
      const int k = static_cast<int>(r / NY);
      const std::uint8_t* row = mask.Row(j, k);
      const std::uint8_t *ym = ex.VoxelRow(j - 1, k), *yp = ex.VoxelRow(j + 1, k);
      const std::uint8_t *zm = ex.VoxelRow(j, k - 1), *zp = ex.VoxelRow(j, k + 1);
      std::int64_t cursor[2][2], rowEnd[2][2];
      for (int dk = 0; dk < 2; ++dk)
      {
        for (int dj = 0; dj < 2; ++dj)
        {
          const std::int64_t cr = static_cast<std::int64_t>(k + dk) * (NY + 1) + (j + dj);
          cursor[dk][dj] = pointOffsets[cr];
          rowEnd[dk][dj] = pointOffsets[cr + 1];
        }
      }
      std::int64_t s = surfelOffsets[r];
      for (int i = mask.RowMin[r]; i <= mask.RowMax[r]; ++i)
      {
        if (!row[i + 1])
        {
          continue;
        }
        const int faces = ex.Faces(row, ym, yp, zm, zp, i);
        if (!faces)
        {
          continue;
        }
        // Ids of the voxel's 8 corners that exist (only those on a face are used).
        std::int64_t ids[2][2][2];
        for (int dk = 0; dk < 2; ++dk)
        {
          for (int dj = 0; dj < 2; ++dj)
          {
            std::int64_t& cur = cursor[dk][dj];
            const std::int64_t e = rowEnd[dk][dj];
            while (cur < e && out.Corners[3 * cur] < i)
            {
              ++cur;
            }
            std::int64_t p = cur;
            ids[dk][dj][0] = (p < e && out.Corners[3 * p] == i) ? p++ : -1;
            ids[dk][dj][1] = (p < e && out.Corners[3 * p] == i + 1) ? p : -1;
          }
        }
        for (int d = 0; d < 6; ++d)
        {
          if (!(faces & (1 << d)))
          {
            continue;
          }
          for (int c = 0; c < 4; ++c)
          {
            const int* o = QuadCorners[d][c];
            const std::int64_t id = ids[o[2]][o[1]][o[0]];
            assert(id >= 0);
            out.Quads[4 * s + c] = id;
          }
          out.Voxels[3 * s] = i;
          out.Voxels[3 * s + 1] = j;
          out.Voxels[3 * s + 2] = k;
          out.Directions[s] = static_cast<std::uint8_t>(d);
          ++s;
        }
      }
    }
  };
  const std::int64_t slabs = std::max<std::int64_t>(1, std::min<std::int64_t>(20, nVoxelRows / 64));
  for (std::int64_t b = 0; b < slabs; ++b)
  {
    vtkSMPTools::For(nVoxelRows * b / slabs, nVoxelRows * (b + 1) / slabs, pass3);
    if (!report(0.7 + 0.3 * (b + 1) / slabs))
    {
      return false;
    }
  }
  return true;
}

} // namespace dg
