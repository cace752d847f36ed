// Solids from mesh files (issue 43; core/solid_mesh.hpp, `type: mesh` in docs/case-file.md): a box
// and a sphere written here as STL files fill to the particle counts of their volumes within one
// layer, as fluid and as wall surface layers; the units and the transform move and turn them;
// an open or self-intersecting mesh, a 2D mesh shape and a bad units value are InputErrors naming
// the case file's line, the key and the file.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/core/fields.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/setup/setup.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

using Tri = std::array<std::array<double, 3>, 3>;

std::string write_stl(const std::string& name, const std::vector<Tri>& tris) {
  const auto dir = std::filesystem::temp_directory_path() / "sphflume_mesh_test";
  std::filesystem::create_directories(dir);
  const auto p = dir / name;
  std::ofstream out(p);
  out.precision(17);
  out << "solid " << name << "\n";
  for (const auto& t : tris) {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (const auto& v : t) out << "   vertex " << v[0] << " " << v[1] << " " << v[2] << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid " << name << "\n";
  return p.string();
}

/// The 12 triangles of the box [lo, hi] (outward), `skip` faces left out (an open box).
std::vector<Tri> box(const std::array<double, 3>& lo, const std::array<double, 3>& hi, int skip = 0) {
  std::array<std::array<double, 3>, 8> c;
  for (int i = 0; i < 8; ++i) c[i] = {i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]};
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<Tri> t;
  for (int f = skip; f < 6; ++f) {
    const auto& q = quads[f];
    t.push_back({c[q[0]], c[q[1]], c[q[2]]});
    t.push_back({c[q[0]], c[q[2]], c[q[3]]});
  }
  return t;
}

/// An icosphere of radius r about o (4^level x 20 triangles, vertices on the sphere).
std::vector<Tri> sphere(const std::array<double, 3>& o, double r, int level) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<std::array<double, 3>> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                          {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                       {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                       {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  auto unit = [](std::array<double, 3> a) {
    const double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return std::array<double, 3>{a[0] / n, a[1] / n, a[2] / n};
  };
  for (auto& p : v) p = unit(p);
  std::vector<Tri> t;
  for (const auto& q : f) t.push_back({v[q[0]], v[q[1]], v[q[2]]});
  for (int l = 0; l < level; ++l) {
    std::vector<Tri> next;
    for (const auto& a : t) {
      std::array<std::array<double, 3>, 3> m;
      for (int e = 0; e < 3; ++e)
        m[e] = unit({(a[e][0] + a[(e + 1) % 3][0]) / 2, (a[e][1] + a[(e + 1) % 3][1]) / 2, (a[e][2] + a[(e + 1) % 3][2]) / 2});
      next.push_back({a[0], m[0], m[2]});
      next.push_back({m[0], a[1], m[1]});
      next.push_back({m[2], m[1], a[2]});
      next.push_back({m[0], m[1], m[2]});
    }
    t = next;
  }
  for (auto& a : t)
    for (auto& p : a)
      for (int d = 0; d < 3; ++d) p[d] = o[d] + r * p[d];
  return t;
}

constexpr double kDx = 0.02;

/// A tank of water 0.1 m deep with the shape (YAML flow mapping) in it.
std::string tank_case(const std::string& shape, int dim = 3) {
  if (dim == 2)
    return "dimension: 2\nparticles: {dx: 0.02}\nfluid: {density: 1000.0}\ngeometry:\n"
           "  - {type: tank, min: [0.0, 0.0], max: [1.0, 0.6]}\n  - " + shape + "\n"
           "  - {type: box, fill: fluid, min: [0.0, 0.0], max: [1.0, 0.1]}\ntime: {end: 0.1}\n";
  return "dimension: 3\nparticles: {dx: 0.02}\nfluid: {density: 1000.0}\ngeometry:\n"
         "  - {type: tank, min: [0.0, 0.0, 0.0], max: [1.0, 0.6, 0.6]}\n  - " + shape + "\n"
         "  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [1.0, 0.6, 0.1]}\ntime: {end: 0.1}\n";
}

struct Counts {
  std::size_t fluid = 0, wall = 0;
};
Counts counts(const std::string& text) {
  const Case c = parse_case(text, "case.yaml");
  System<3> S;
  build_system<3>(c, S);
  Counts n;
  for (std::size_t i = 0; i < S.particles.size(); ++i) {
    n.fluid += S.particles.kind[i] == Kind::Fluid ? 1 : 0;
    n.wall += S.particles.kind[i] == Kind::Wall ? 1 : 0;
  }
  return n;
}

std::string error_of(const std::string& text, int dim = 3) {
  return dim == 3 ? test::build_error<3>(text) : test::build_error<2>(text);
}


}  // namespace

// A box on the lattice (corners on the dx grid): the mesh gives the particles of the same box
// typed in the case, as fluid (every lattice point inside) and as wall (the points within the
// wall layers of its surface: the inside minus the core deeper than the layers).
TEST(Mesh, BoxGivesTheTypedBoxsParticles) {
  const std::array<double, 3> lo{0.4, 0.2, 0.2}, hi{0.6, 0.4, 0.36};
  const std::string stl = write_stl("box.stl", box(lo, hi));
  const Counts tank = counts(tank_case("{type: box, fill: fluid, min: [0.1, 0.1, 0.42], max: [0.12, 0.12, 0.44]}"));
  const Counts typed = counts(tank_case("{type: box, fill: fluid, min: [0.4, 0.2, 0.2], max: [0.6, 0.4, 0.36]}"));
  const Counts mesh = counts(tank_case("{type: mesh, fill: fluid, file: " + stl + "}"));
  EXPECT_EQ(mesh.fluid, typed.fluid);
  EXPECT_EQ(mesh.fluid - (tank.fluid - 1), 10u * 10u * 8u);  // (the tank case's one-particle marker box apart)
  const Counts wall = counts(tank_case("{type: mesh, fill: wall, file: " + stl + "}"));
  const int layers = 3;  // (the dummy walls' default layers at h = 1.3 dx)
  const std::size_t core = (10 - 2 * layers) * (10 - 2 * layers) * (8 - 2 * layers);
  EXPECT_EQ(wall.wall - (tank.wall), 10u * 10u * 8u - core);
  EXPECT_EQ(wall.fluid, tank.fluid - 1);  // the body is above the water: none dropped
}

// A sphere: the fluid count is the mesh's volume in dx^3 within one layer of its surface
// (|N dx^3 - V| < A dx), and moved by the transform (mm, a scale, a rotation, an offset) it
// lands where the offset puts it, with the count of the same solid.
TEST(Mesh, SphereFillsItsVolumeWithinOneLayer) {
  const double r = 0.12;
  const std::string stl = write_stl("sphere.stl", sphere({0.5, 0.3, 0.3}, r, 3));
  const Counts base = counts(tank_case("{type: box, fill: fluid, min: [0.1, 0.1, 0.42], max: [0.12, 0.12, 0.44]}"));
  const Counts n = counts(tank_case("{type: mesh, fill: fluid, file: " + stl + "}"));
  const double volume = 4.0 / 3.0 * std::acos(-1.0) * r * r * r, area = 4.0 * std::acos(-1.0) * r * r;
  const double filled = double(n.fluid - (base.fluid - 1)) * kDx * kDx * kDx;
  EXPECT_LT(std::abs(filled - volume), area * kDx) << filled << " vs " << volume;
  EXPECT_GT(filled, 0.9 * volume);
  // the same sphere in mm about the origin, scaled 2 and back by 0.5, turned, and offset
  const std::string mm = write_stl("sphere_mm.stl", sphere({0.0, 0.0, 0.0}, 1000.0 * r, 3));
  const Counts moved = counts(tank_case("{type: mesh, fill: fluid, file: " + mm +
                                        ", units: mm, scale: 1.0, rotate: [0, 0, 0], offset: [0.5, 0.3, 0.3]}"));
  EXPECT_EQ(moved.fluid, n.fluid);
  const Counts turned = counts(tank_case("{type: mesh, fill: fluid, file: " + mm +
                                         ", units: mm, scale: 1.0, rotate: [20, 35, 50], offset: [0.5, 0.3, 0.3]}"));
  const double turned_v = double(turned.fluid - (base.fluid - 1)) * kDx * kDx * kDx;
  EXPECT_LT(std::abs(turned_v - volume), area * kDx);
}

// Bad meshes and keys: an InputError naming the case file's line, the key and the file.
TEST(Mesh, BadMeshesAreRefusedWithTheirLine) {
  const std::string open = write_stl("open_box.stl", box({0.4, 0.2, 0.2}, {0.6, 0.4, 0.36}, 1));
  std::string e = error_of(tank_case("{type: mesh, fill: wall, file: " + open + "}"));
  EXPECT_HAS(e, "line 6");
  EXPECT_HAS(e, "geometry.1.file");
  EXPECT_HAS(e, open);
  EXPECT_HAS(e, "open mesh (4 border edges)");
  auto two = box({0.4, 0.2, 0.2}, {0.6, 0.4, 0.36});
  const auto other = box({0.5, 0.3, 0.3}, {0.7, 0.5, 0.46});
  two.insert(two.end(), other.begin(), other.end());
  e = error_of(tank_case("{type: mesh, fill: wall, file: " + write_stl("overlap.stl", two) + "}"));
  EXPECT_HAS(e, "intersects itself");
  e = error_of(tank_case("{type: mesh, file: no_such.stl}"));
  EXPECT_HAS(e, "no_such.stl: no such file");
  const std::string ok = write_stl("ok.stl", box({0.4, 0.2, 0.2}, {0.6, 0.4, 0.36}));
  e = error_of(tank_case("{type: mesh, file: " + ok + ", units: inch}"));
  EXPECT_HAS(e, "geometry.1.units");
  EXPECT_HAS(e, "line 6");
  e = error_of(tank_case("{type: mesh, file: " + ok + ", unit: mm}"));
  EXPECT_HAS(e, "did you mean 'geometry.1.units'?");
  e = error_of(tank_case("{type: mesh, file: " + ok + ", scale: 0}"));
  EXPECT_HAS(e, "geometry.1.scale");
  e = error_of(tank_case("{type: mesh, file: " + ok + "}", 2), 2);
  EXPECT_HAS(e, "meshes are 3D");
}

// A porous region drawn as a mesh: the box's STL gives the particles of the typed porous box
// (its fill at dx/φ0^(1/3) inside it), and φ = φ0 deep inside it, 1 far outside.
TEST(Mesh, PorousMeshRegionGivesTheTypedBoxsFill) {
  const std::string stl = write_stl("porous_box.stl", box({0.4, 0.2, 0.0}, {0.6, 0.4, 0.16}));
  auto porous_case = [](const std::string& region) {
    return "dimension: 3\nparticles: {dx: 0.02}\nfluid: {density: 1000.0}\ngeometry:\n"
           "  - {type: tank, min: [0.0, 0.0, 0.0], max: [1.0, 0.6, 0.4]}\n"
           "  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [1.0, 0.6, 0.2]}\n"
           "porous:\n  regions:\n    - " + region + "\ntime: {end: 0.1}\n";
  };
  const std::string keys = "porosity: 0.4, diameter: 0.02, closure: {type: ergun, c1: 150, c2: 1.75}";
  auto build = [&](const std::string& region, System<3>& S) { build_system<3>(parse_case(porous_case(region), "case.yaml"), S); };
  System<3> typed, mesh;
  build("{shape: box, min: [0.4, 0.2, 0.0], max: [0.6, 0.4, 0.16], " + keys + "}", typed);
  build("{shape: mesh, file: " + stl + ", " + keys + "}", mesh);
  ASSERT_EQ(mesh.particles.size(), typed.particles.size());
  const auto& phi = mesh.particles.scalar(field::porosity);
  std::size_t deep = 0, far = 0;
  for (std::size_t i = 0; i < mesh.particles.size(); ++i) {
    if (mesh.particles.kind[i] != Kind::Fluid) continue;
    const auto& x = mesh.particles.pos[i];
    const bool in = x[0] > 0.45 && x[0] < 0.55 && x[1] > 0.25 && x[1] < 0.35 && x[2] > 0.05 && x[2] < 0.11;
    const bool out = x[0] < 0.3 || x[0] > 0.7;
    if (in) { EXPECT_NEAR(phi[i], 0.4, 1e-9); ++deep; }
    if (out) { EXPECT_EQ(phi[i], 1.0); ++far; }
  }
  EXPECT_GT(deep, 10u);
  EXPECT_GT(far, 1000u);
}

// Resolution regions in 3D (issue 58): `shape: mesh` (inside a closed surface or within `margin` of it, read from
// the solid's distance on a grid of the case's spacing) and `shape: cylinder` (a vertical axis). The grid's reading
// is within √3/2 of its spacing (0.02 m here) of the exact distance, so points 0.02 m nearer than the margin (off a
// face and off an edge) are in and points 0.02 m farther are out; set-up then refines exactly the fluid the region
// holds (each fill point's level is the region's where it contains the point, a refined point's children lying
// within √3 dx/4 of it; the interface relaxation is off here).
TEST(Mesh, MeshAndCylinderRegionsRefine3D) {
  const std::string stl = write_stl("region_box.stl", box({0.4, 0.2, 0.0}, {0.6, 0.4, 0.16}));
  const double margin = 0.05, tol = 0.02;
  const std::string text = tank_case("{type: mesh, fill: wall, file: " + stl + "}") +
                           "resolution:\n  relax: 0\n  regions:\n    - {shape: mesh, file: " + stl + ", margin: 0.05, level: 1}\n"
                           "    - {shape: cylinder, center: [0.85, 0.3], radius: 0.08, z_max: 0.2, level: 1}\n";
  const Case c = parse_case(text, "case.yaml");
  ASSERT_EQ(c.resolution.regions.size(), 2u);
  const auto& mesh = c.resolution.regions[0].region;
  const auto& cyl = c.resolution.regions[1].region;
  auto in = [](const RegionConfig& r, double x, double y, double z) {
    const double p[3] = {x, y, z};
    return r.contains(p, 3);
  };
  EXPECT_TRUE(in(mesh, 0.5, 0.3, 0.08));                                 // inside
  EXPECT_TRUE(in(mesh, 0.6 + margin - tol, 0.3, 0.08));                   // off the +x face
  EXPECT_FALSE(in(mesh, 0.6 + margin + tol, 0.3, 0.08));
  EXPECT_TRUE(in(mesh, 0.5, 0.3, 0.16 + margin - tol));                   // above the top
  EXPECT_FALSE(in(mesh, 0.5, 0.3, 0.16 + margin + tol));
  const double e = (margin - tol) / std::sqrt(2.0), f = (margin + tol) / std::sqrt(2.0);
  EXPECT_TRUE(in(mesh, 0.6 + e, 0.4 + e, 0.08));                          // off the vertical edge
  EXPECT_FALSE(in(mesh, 0.6 + f, 0.4 + f, 0.08));
  EXPECT_FALSE(in(mesh, 0.9, 0.5, 0.5));                                  // beyond the grid
  EXPECT_TRUE(in(cyl, 0.85, 0.37, 0.1));
  EXPECT_FALSE(in(cyl, 0.85, 0.39, 0.1));
  EXPECT_FALSE(in(cyl, 0.85, 0.3, 0.21));
  // the fill: the fluid 0.1 m deep about the block (a wall), refined around it and in the cylinder only
  System<3> S;
  build_system<3>(c, S);
  ASSERT_EQ(S.levels, 1);
  const auto& P = S.particles;
  const auto& lv = P.require(field::level);
  auto dist = [](const Vec<3>& x) {  // to the box [0.4, 0.6] x [0.2, 0.4] x [0, 0.16] (0 inside)
    const double lo[3] = {0.4, 0.2, 0.0}, hi[3] = {0.6, 0.4, 0.16};
    double s = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double o = std::max({lo[d] - x[d], 0.0, x[d] - hi[d]});
      s += o * o;
    }
    return std::sqrt(s);
  };
  std::size_t fine = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const auto& x = P.pos[i];
    const double rc = std::hypot(x[0] - 0.85, x[1] - 0.3);
    // a level-0 point the region contains is split into children ±dx/4 about it (√3 dx/4 away at most)
    const double child = 0.25 * std::sqrt(3.0) * kDx;
    if (lv[i] > 0.0) {
      ++fine;
      EXPECT_TRUE(dist(x) <= margin + tol + child || rc <= 0.08 + child) << x[0] << ", " << x[1] << ", " << x[2];
    } else {
      EXPECT_TRUE(dist(x) >= margin - tol && rc >= 0.08) << x[0] << ", " << x[1] << ", " << x[2];
    }
  }
  EXPECT_GT(fine, 1000u);
  // shapes a 2D case cannot have
  EXPECT_HAS(error_of(tank_case("{type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}", 2) +
                      "resolution: {regions: [{shape: cylinder, center: [0.5, 0.3], radius: 0.1}]}\n", 2),
             "cylinders and meshes are 3D regions");
}
