// Particle store: permutation keeps every field with its particle; removal compacts; images
// carry their source's fields with the displacement.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "sphflume/core/particles.hpp"

using namespace sph;

TEST(ParticleStore, PermuteKeepsFieldsTogether) {
  ParticleStore<2> P;
  for (int i = 0; i < 100; ++i) P.add(Vec<2>{{double(i), 0.0}}, Vec<2>{{0.0, double(i)}}, 1000.0 + i, i * 0.5, Kind::Fluid);
  auto& c = P.scalar("concentration");
  for (int i = 0; i < 100; ++i) c[i] = 3.0 * i;
  std::vector<std::uint32_t> perm(100);
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(5));
  P.permute(perm);
  for (std::size_t i = 0; i < 100; ++i) {
    const double k = P.pos[i][0];
    EXPECT_EQ(P.id[i], static_cast<std::uint32_t>(k));
    EXPECT_EQ(P.vel[i][1], k);
    EXPECT_EQ(P.rho[i], 1000.0 + k);
    EXPECT_EQ(P.mass[i], 0.5 * k);
    EXPECT_EQ(P.scalar("concentration")[i], 3.0 * k);
  }
}

TEST(ParticleStore, RemoveFlaggedCompacts) {
  ParticleStore<3> P;
  for (int i = 0; i < 10; ++i) P.add(Vec<3>{{double(i), 0, 0}}, Vec<3>{}, 1.0, 1.0, Kind::Fluid);
  std::vector<char> flag(10, 0);
  flag[2] = flag[7] = 1;
  EXPECT_EQ(P.remove_if_flagged(flag), 2u);
  EXPECT_EQ(P.n_owned(), 8u);
  for (std::size_t i = 0; i < P.n_owned(); ++i) EXPECT_EQ(P.pos[i][0], double(P.id[i]));
}

TEST(ParticleStore, ImagesFollowTheirSource) {
  ParticleStore<2> P;
  P.add(Vec<2>{{0.1, 0.2}}, Vec<2>{{1.0, 0.0}}, 1000.0, 1.0, Kind::Wall);
  P.add_image(0, Vec<2>{{1.0, 0.0}});
  EXPECT_EQ(P.size(), 2u);
  EXPECT_EQ(P.n_owned(), 1u);
  P.pos[0][1] = 0.3;
  P.rho[0] = 1010.0;
  P.refresh_images(P.n_owned(), P.size());
  EXPECT_DOUBLE_EQ(P.pos[1][0], 1.1);
  EXPECT_DOUBLE_EQ(P.pos[1][1], 0.3);
  EXPECT_EQ(P.rho[1], 1010.0);
  EXPECT_EQ(P.kind[1], Kind::Wall);
  P.clear_images();
  EXPECT_EQ(P.size(), 1u);
}

// a permutation long enough for the fields to be cycled in parallel, with named scalar and
// vector fields: every field follows its particle
TEST(ParticleStore, LongPermuteKeepsEveryFieldTogether) {
  ParticleStore<3> P;
  const int n = 20000;
  for (int i = 0; i < n; ++i) P.add(Vec<3>{{double(i), 0.0, 1.0}}, Vec<3>{{0.0, double(i), 0.0}}, 1000.0 + i, i * 0.5, i % 3 ? Kind::Fluid : Kind::Wall);
  auto& c = P.scalar("concentration");
  auto& w = P.vector(field::wall_to_surface);
  for (int i = 0; i < n; ++i) { c[i] = 3.0 * i; w[i] = Vec<3>{{0.0, 0.0, -double(i)}}; }
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(7));
  P.permute(perm);
  for (int i = 0; i < n; ++i) {
    ASSERT_EQ(P.pos[i][0], double(perm[i]));
    const double k = P.pos[i][0];
    ASSERT_EQ(P.id[i], static_cast<std::uint32_t>(k));
    ASSERT_EQ(P.vel[i][1], k);
    ASSERT_EQ(P.rho[i], 1000.0 + k);
    ASSERT_EQ(P.kind[i], static_cast<int>(k) % 3 ? Kind::Fluid : Kind::Wall);
    ASSERT_EQ(P.scalar("concentration")[i], 3.0 * k);
    ASSERT_EQ(P.vector(field::wall_to_surface)[i][2], -k);
  }
}

// Typed field handles (core/fields.hpp): a field the set-up did not create is named when required,
// and the handle and the name reach the same storage.
TEST(ParticleStore, RequiredFieldMissingIsNamed) {
  ParticleStore<2> P;
  P.add(Vec<2>{{0.0, 0.0}}, Vec<2>{}, 1000.0, 1.0, Kind::Wall);
  try {
    (void)P.require(field::wall_to_surface);
    FAIL() << "require() of a field never created returned";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'wall_to_surface'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(P.find(field::porosity), nullptr);
  P.scalar(field::porosity)[0] = 0.4;
  EXPECT_TRUE(P.has(field::porosity));
  EXPECT_EQ(P.require(field::porosity)[0], 0.4);
  EXPECT_EQ(&P.scalar(std::string("porosity")), &P.scalar(field::porosity));  // the same storage by name
}
