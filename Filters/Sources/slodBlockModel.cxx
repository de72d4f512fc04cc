// SPDX-License-Identifier: BSD-3-Clause
#include "slodBlockModel.h"

#include <algorithm>
#include <map>
#include <cmath>
#include <tuple>

namespace slod
{
TriangleMesh BlockModel(int nx, int ny, const std::vector<double>& heights, double cellSize, int subdivisions)
{
  TriangleMesh mesh;
  const int s = std::max(1, subdivisions);
  const int fx = nx * s, fy = ny * s; // fine cells
  auto height = [&](int i, int j) -> double {
    if (i < 0 || j < 0 || i >= fx || j >= fy)
    {
      return 0.0;
    }
    return std::max(0.0, heights[size_t(i / s) + size_t(nx) * size_t(j / s)]);
  };
  const double step = cellSize / s;
  std::map<std::tuple<int, int, double>, Index> ids;
  auto vertex = [&](int gx, int gy, double z) {
    auto found = ids.find(std::make_tuple(gx, gy, z));
    if (found != ids.end())
    {
      return found->second;
    }
    const Index v = mesh.AddPoint({ gx * step, gy * step, z });
    ids.emplace(std::make_tuple(gx, gy, z), v);
    return v;
  };
  // Heights present at a grid point (sorted, unique): 0 and the top of every column around it.
  auto levels = [&](int gx, int gy) {
    std::vector<double> z;
    for (int dj = -1; dj <= 0; ++dj)
    {
      for (int di = -1; di <= 0; ++di)
      {
        const double h = height(gx + di, gy + dj);
        if (h > 0)
        {
          z.push_back(0.0);
          z.push_back(h);
        }
      }
    }
    std::sort(z.begin(), z.end());
    z.erase(std::unique(z.begin(), z.end()), z.end());
    return z;
  };
  auto quad = [&](Index a, Index b, Index c, Index d) {
    mesh.AddTriangle(a, b, c);
    mesh.AddTriangle(a, c, d);
  };
  for (int j = 0; j < fy; ++j)
  {
    for (int i = 0; i < fx; ++i)
    {
      const double h = height(i, j);
      if (h <= 0)
      {
        continue;
      }
      quad(vertex(i, j, h), vertex(i + 1, j, h), vertex(i + 1, j + 1, h), vertex(i, j + 1, h));
      quad(vertex(i, j, 0), vertex(i, j + 1, 0), vertex(i + 1, j + 1, 0), vertex(i + 1, j, 0));
    }
  }
  // Wall along grid points p -> q whose outward normal is (q - p) x z: the column on the left of
  // p -> q (seen from above) is higher. Zipped between the levels at p and at q.
  auto wall = [&](int px, int py, int qx, int qy, double lo, double hi) {
    std::vector<double> left, right;
    for (double z : levels(px, py))
    {
      if (z >= lo && z <= hi)
      {
        left.push_back(z);
      }
    }
    for (double z : levels(qx, qy))
    {
      if (z >= lo && z <= hi)
      {
        right.push_back(z);
      }
    }
    size_t a = 0, b = 0;
    while (a + 1 < left.size() || b + 1 < right.size())
    {
      const bool advanceRight = a + 1 >= left.size() || (b + 1 < right.size() && right[b + 1] <= left[a + 1]);
      if (advanceRight)
      {
        mesh.AddTriangle(vertex(px, py, left[a]), vertex(qx, qy, right[b]), vertex(qx, qy, right[b + 1]));
        ++b;
      }
      else
      {
        mesh.AddTriangle(vertex(px, py, left[a]), vertex(qx, qy, right[b]), vertex(px, py, left[a + 1]));
        ++a;
      }
    }
  };
  // Edges along x (between cells (i, j - 1) and (i, j)) and along y.
  for (int j = 0; j <= fy; ++j)
  {
    for (int i = 0; i < fx; ++i)
    {
      const double below = height(i, j - 1), above = height(i, j);
      if (above > below)
      {
        wall(i, j, i + 1, j, below, above); // column on +y: outward -y = (+x) x z
      }
      else if (below > above)
      {
        wall(i + 1, j, i, j, above, below);
      }
    }
  }
  for (int i = 0; i <= fx; ++i)
  {
    for (int j = 0; j < fy; ++j)
    {
      const double west = height(i - 1, j), east = height(i, j);
      if (east > west)
      {
        wall(i, j + 1, i, j, west, east); // column on +x: outward -x = (-y) x z
      }
      else if (west > east)
      {
        wall(i, j, i, j + 1, east, west);
      }
    }
  }
  return mesh;
}

TriangleMesh PlateWithHoles(int holesX, int holesY, double thickness, int subdivisions)
{
  const int nx = 2 * holesX + 1, ny = 2 * holesY + 1;
  std::vector<double> heights(size_t(nx) * size_t(ny), thickness);
  for (int j = 1; j < ny; j += 2)
  {
    for (int i = 1; i < nx; i += 2)
    {
      heights[size_t(i) + size_t(nx) * size_t(j)] = 0.0;
    }
  }
  return BlockModel(nx, ny, heights, 1.0, subdivisions);
}

TriangleMesh PlateWithRoundHoles(int tilesX, int tilesY, double radius, int segments, double thickness)
{
  TriangleMesh mesh;
  const int q = std::max(2, segments / 4); // border steps per tile side
  const int n = 4 * q;
  std::map<std::tuple<int, int, int>, Index> lattice; // (x, y, top) in steps -> vertex
  auto border = [&](int x, int y, int top) {
    const auto key = std::make_tuple(x, y, top);
    auto found = lattice.find(key);
    if (found != lattice.end())
    {
      return found->second;
    }
    const Index v = mesh.AddPoint({ double(x) / q, double(y) / q, top ? thickness : 0.0 });
    lattice.emplace(key, v);
    return v;
  };
  // Border position i (0..n-1) of a tile, counter-clockwise from its lower-left corner.
  auto step = [&](int i, int& dx, int& dy) {
    const int side = i / q, k = i % q;
    dx = side == 0 ? k : (side == 1 ? q : (side == 2 ? q - k : 0));
    dy = side == 0 ? 0 : (side == 1 ? k : (side == 2 ? q : q - k));
  };
  const double pi = 3.14159265358979323846;
  for (int ty = 0; ty < tilesY; ++ty)
  {
    for (int tx = 0; tx < tilesX; ++tx)
    {
      std::vector<Index> circle[2], square[2];
      for (int i = 0; i < n; ++i)
      {
        const double angle = -0.75 * pi + 2.0 * pi * i / n;
        int dx, dy;
        step(i, dx, dy);
        for (int top = 0; top < 2; ++top)
        {
          circle[top].push_back(mesh.AddPoint(
            { tx + 0.5 + radius * std::cos(angle), ty + 0.5 + radius * std::sin(angle), top ? thickness : 0.0 }));
          square[top].push_back(border(tx * q + dx, ty * q + dy, top));
        }
      }
      for (int i = 0; i < n; ++i)
      {
        const int j = (i + 1) % n;
        // Top ring (normal +z), bottom ring (normal -z), hole wall (normal toward the axis).
        mesh.AddTriangle(square[1][i], square[1][j], circle[1][j]);
        mesh.AddTriangle(square[1][i], circle[1][j], circle[1][i]);
        mesh.AddTriangle(square[0][j], square[0][i], circle[0][i]);
        mesh.AddTriangle(square[0][j], circle[0][i], circle[0][j]);
        mesh.AddTriangle(circle[1][i], circle[1][j], circle[0][j]);
        mesh.AddTriangle(circle[1][i], circle[0][j], circle[0][i]);
      }
    }
  }
  // Outer walls along the plate border, counter-clockwise seen from above (outward normals).
  std::vector<std::pair<int, int>> perimeter;
  const int w = tilesX * q, h = tilesY * q;
  for (int x = 0; x < w; ++x)
  {
    perimeter.emplace_back(x, 0);
  }
  for (int y = 0; y < h; ++y)
  {
    perimeter.emplace_back(w, y);
  }
  for (int x = w; x > 0; --x)
  {
    perimeter.emplace_back(x, h);
  }
  for (int y = h; y > 0; --y)
  {
    perimeter.emplace_back(0, y);
  }
  for (size_t i = 0; i < perimeter.size(); ++i)
  {
    const auto& a = perimeter[i];
    const auto& b = perimeter[(i + 1) % perimeter.size()];
    const Index ta = border(a.first, a.second, 1), ba = border(a.first, a.second, 0);
    const Index tb = border(b.first, b.second, 1), bb = border(b.first, b.second, 0);
    mesh.AddTriangle(ta, ba, bb);
    mesh.AddTriangle(ta, bb, tb);
  }
  return mesh;
}
} // namespace slod
