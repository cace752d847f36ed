// Snapshot files as restart points (io/snapshot, io/restart): what a run writes is what a restart reads, every field
// to the bit, in 2D and 3D, for a store large enough that HDF5's in-memory file grows through several buffers (the
// writer saves the driver's own buffer, followed through the file image callbacks, instead of a copy of it).
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

#include "sphflume/io/restart.hpp"
#include "sphflume/io/snapshot.hpp"

using namespace sph;

namespace {

template <int D>
ParticleStore<D> random_store(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&] {
    Vec<D> v;
    for (int d = 0; d < D; ++d) v[d] = u(rng);
    return v;
  };
  ParticleStore<D> P;
  for (std::size_t i = 0; i < n; ++i) P.add(vec(), vec(), 1000.0 + u(rng), 0.01 * (2.0 + u(rng)), i % 7 == 0 ? Kind::Wall : Kind::Fluid);
  auto& c = P.scalar("concentration");
  auto& w = P.vector(field::wall_to_surface);
  for (std::size_t i = 0; i < n; ++i) {
    P.p[i] = 1e4 * u(rng);
    P.acc[i] = vec();
    P.drho[i] = u(rng);
    P.id[i] = static_cast<std::uint32_t>(3 * (n - i));  // (not the store order)
    c[i] = u(rng);
    w[i] = vec();
  }
  return P;
}

template <int D>
void round_trip(std::size_t n) {
  const auto dir = std::filesystem::temp_directory_path() / ("sphflume_snapshot_io_" + std::to_string(D));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const ParticleStore<D> P = random_store<D>(n, 11u + D);
  RunState rs;
  rs.time = 1.25;
  rs.step = 4242;
  rs.case_text = "name: round_trip\n";
  SnapshotWriter<D> writer(dir.string());
  const std::string path = (dir / "checkpoint.h5").string();
  writer.write_checkpoint(path, P, rs);
  // HDF5's core driver grows its file 1 MiB at a time: the file spans several of its buffers
  ASSERT_GT(std::filesystem::file_size(path), std::uintmax_t(3) << 20);

  ParticleStore<D> Q;
  RunState back;
  read_restart<D>(path, Q, back);
  ASSERT_EQ(Q.size(), n);
  EXPECT_EQ(back.step, rs.step);
  EXPECT_EQ(back.time, rs.time);
  EXPECT_EQ(back.case_text, rs.case_text);
  const auto& c = Q.scalar("concentration");
  const auto& w = Q.vector(field::wall_to_surface);
  const auto& c0 = *P.find_scalar("concentration");
  const auto& w0 = *P.find(field::wall_to_surface);
  std::size_t bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool same = Q.id[i] == P.id[i] && Q.kind[i] == P.kind[i] && Q.rho[i] == P.rho[i] && Q.p[i] == P.p[i] &&
                Q.mass[i] == P.mass[i] && Q.drho[i] == P.drho[i] && c[i] == c0[i];
    for (int d = 0; d < D; ++d)
      same = same && Q.pos[i][d] == P.pos[i][d] && Q.vel[i][d] == P.vel[i][d] && Q.acc[i][d] == P.acc[i][d] &&
             w[i][d] == w0[i][d];
    bad += same ? 0 : 1;
  }
  EXPECT_EQ(bad, 0u) << "particles whose fields did not come back bit for bit";
  std::filesystem::remove_all(dir);
}

}  // namespace

TEST(SnapshotIo, RestartPointRoundTripsEveryField2D) { round_trip<2>(40000); }
TEST(SnapshotIo, RestartPointRoundTripsEveryField3D) { round_trip<3>(30000); }
