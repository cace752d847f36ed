// MPI ranks: the communicator over MPI_COMM_WORLD and the slab decomposition (ranks.hpp).
// the C API only (OpenMPI's C++ bindings would need libmpi_cxx)
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#include <hdf5.h>  // (the parallel HDF5 build's, when it is the one found: H5_HAVE_PARALLEL)
#include <type_traits>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "sphflume/core/errors.hpp"
#include "sphflume/sim/ranks.hpp"

namespace sph {
namespace {

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void sum(double* v, std::size_t n) const override { reduce(v, n, MPI_DOUBLE, MPI_SUM); }
  void sum(std::uint64_t* v, std::size_t n) const override { reduce(v, n, MPI_UINT64_T, MPI_SUM); }
  void min(double* v, std::size_t n) const override { reduce(v, n, MPI_DOUBLE, MPI_MIN); }
  void max(double* v, std::size_t n) const override { reduce(v, n, MPI_DOUBLE, MPI_MAX); }
  std::vector<double> allgather(const std::vector<double>& v) const override {
    std::vector<int> counts(static_cast<std::size_t>(size_)), displ(counts.size());
    const int n = static_cast<int>(v.size());
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    int total = 0;
    for (std::size_t q = 0; q < counts.size(); ++q) { displ[q] = total; total += counts[q]; }
    std::vector<double> all(static_cast<std::size_t>(total));
    MPI_Allgatherv(v.data(), n, MPI_DOUBLE, all.data(), counts.data(), displ.data(), MPI_DOUBLE, MPI_COMM_WORLD);
    return all;
  }
  bool parallel_hdf5(std::int64_t fapl, std::int64_t dxpl) const override {
#ifdef H5_HAVE_PARALLEL
    static_assert(std::is_same_v<hid_t, std::int64_t>, "hid_t is passed as a 64-bit integer");
    if (fapl >= 0 && H5Pset_fapl_mpio(fapl, MPI_COMM_WORLD, MPI_INFO_NULL) < 0) return false;
    if (dxpl >= 0 && H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE) < 0) return false;
    return true;
#else
    (void)fapl;
    (void)dxpl;
    return false;
#endif
  }
  std::uint64_t exscan(std::uint64_t v, std::uint64_t& total) const override {
    std::vector<std::uint64_t> all(static_cast<std::size_t>(size_));
    MPI_Allgather(&v, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
    std::uint64_t before = 0;
    total = 0;
    for (int q = 0; q < size_; ++q) {
      if (q < rank_) before += all[static_cast<std::size_t>(q)];
      total += all[static_cast<std::size_t>(q)];
    }
    return before;
  }

 private:
  int rank_ = 0, size_ = 1;
  static void reduce(void* v, std::size_t n, MPI_Datatype t, MPI_Op op) {
    MPI_Allreduce(MPI_IN_PLACE, v, static_cast<int>(n), t, op, MPI_COMM_WORLD);
  }
};

void finalise_mpi() {
  int fin = 0;
  MPI_Finalized(&fin);
  if (!fin) MPI_Finalize();
}

/// All-to-all exchange of byte buffers: send[q] goes to rank q; returns what each rank sent
/// here, back to back in rank order, with recv_counts[q] bytes from rank q.
std::vector<std::byte> exchange_bytes(const std::vector<std::vector<std::byte>>& send, std::vector<int>& recv_counts) {
  const int size = static_cast<int>(send.size());
  std::vector<int> sc(size), sd(size), rd(size);
  recv_counts.assign(size, 0);
  for (int q = 0; q < size; ++q) sc[q] = static_cast<int>(send[q].size());
  MPI_Alltoall(sc.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<std::byte> sbuf;
  int st = 0, rt = 0;
  for (int q = 0; q < size; ++q) {
    sd[q] = st;
    st += sc[q];
    rd[q] = rt;
    rt += recv_counts[q];
    sbuf.insert(sbuf.end(), send[q].begin(), send[q].end());
  }
  std::vector<std::byte> rbuf(static_cast<std::size_t>(rt));
  MPI_Alltoallv(sbuf.data(), sc.data(), sd.data(), MPI_BYTE, rbuf.data(), recv_counts.data(), rd.data(), MPI_BYTE,
                MPI_COMM_WORLD);
  return rbuf;
}

/// The work of particle i in a pair pass, relative to a level-0 fluid particle's: resolution
/// levels (docs/numerics.md §14) keep the level-0 cell list, so a particle of level l among its
/// level's particles scans 2^(D l) times the candidates (`lv`: the level field, or null).
template <int D>
double work_of(const double* lv, std::size_t i) {
  return lv ? double(1 << (D * static_cast<int>(lv[i]))) : 1.0;
}

template <int D>
const double* level_field(const ParticleStore<D>& P) {
  return P.has(field::level) ? P.require(field::level).data() : nullptr;
}

/// Cuts along `axis` that give each of `size` ranks the same work: a histogram of every rank's
/// owned fluid (every particle if there is no fluid), each weighted by work_of (1 without
/// resolution levels: the same number of fluid particles), between the global extremes, summed
/// over the ranks; the same cuts on every rank. `only_root`: every rank holds the same particles
/// (the start), count rank 0's.
template <int D>
std::vector<double> balanced_cuts(const ParticleStore<D>& P, int axis, int size, bool only_root) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (std::size_t i = 0; i < P.n_owned(); ++i) { lo = std::min(lo, P.pos[i][axis]); hi = std::max(hi, P.pos[i][axis]); }
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  constexpr std::size_t kBins = 1 << 14;
  std::vector<double> hist(kBins, 0.0);
  const double span = std::max(hi - lo, 1e-300), scale = kBins / span;
  double total = 0.0;
  const double* lv = level_field(P);
  for (bool all : {false, true}) {
    if (!only_root || rank == 0)
      for (std::size_t i = 0; i < P.n_owned(); ++i) {
        if (!all && !fluid_like(P.kind[i])) continue;
        hist[std::min<std::size_t>(kBins - 1, static_cast<std::size_t>((P.pos[i][axis] - lo) * scale))] += work_of<D>(lv, i);
      }
    MPI_Allreduce(MPI_IN_PLACE, hist.data(), static_cast<int>(kBins), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    for (double h : hist) total += h;
    if (total > 0.0) break;
  }
  std::vector<double> cuts(size + 1);
  cuts[0] = -std::numeric_limits<double>::infinity();
  cuts[size] = std::numeric_limits<double>::infinity();
  double acc = 0.0;
  std::size_t b = 0;
  for (int q = 1; q < size; ++q) {
    const double target = total * q / size;
    while (b < kBins && acc + hist[b] < target) acc += hist[b++];
    cuts[q] = lo + static_cast<double>(b) / scale;  // a bin edge
  }
  return cuts;
}

/// The slab decomposition along one axis: rank r owns [cut[r], cut[r+1]).
template <int D>
class Slabs final : public Halo<D> {
 public:
  Slabs(int axis, std::vector<double> cuts, int rank) : axis_(axis), cut_(std::move(cuts)), rank_(rank) {}
  /// The slab axis is periodic with period [lo, hi): the first and last ranks are neighbours,
  /// their copies shifted by the period (the schemes wrap the owned particles).
  void set_period(double lo, double hi) {
    periodic_ = true;
    plo_ = lo;
    phi_ = hi;
  }
  const char* name() const override { return "mpi"; }
  bool active() const override { return true; }
  int size() const { return static_cast<int>(cut_.size()) - 1; }
  bool owns(const Vec<D>& x) const override { return owner(x[axis_]) == rank_; }
  int owner(double x) const {
    const int q = static_cast<int>(std::upper_bound(cut_.begin() + 1, cut_.end() - 1, x) - (cut_.begin() + 1));
    return std::clamp(q, 0, size() - 1);
  }

  void migrate(ParticleStore<D>& P) override {
    // every kCheckEvery builds: new cuts when the fluid counts (their work, with resolution
    // levels) drifted apart (the flow moved, particles were split or merged)
    if (++builds_ % kCheckEvery == 0) {
      double nf = 0.0;
      const double* lv = level_field(P);
      for (std::size_t i = 0; i < P.n_owned(); ++i) nf += fluid_like(P.kind[i]) ? work_of<D>(lv, i) : 0.0;
      double mx = nf, sum = nf;
      MPI_Allreduce(MPI_IN_PLACE, &mx, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
      MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
      if (sum > 0.0 && mx / (sum / size()) > kRebalanceAbove) {
        cut_ = balanced_cuts(P, axis_, size(), false);
        ++rebalances_;
      }
    }
    const std::size_t n = P.n_owned(), pb = P.packed_bytes();
    std::vector<std::vector<std::byte>> send(size());
    std::vector<char> flag;
    for (std::size_t i = 0; i < n; ++i) {
      const int q = owner(P.pos[i][axis_]);
      if (q == rank_) continue;
      if (flag.empty()) flag.assign(n, 0);
      flag[i] = 1;
      auto& b = send[q];
      b.resize(b.size() + pb);
      P.pack(i, b.data() + b.size() - pb);
    }
    std::vector<int> rc;
    const auto in = exchange_bytes(send, rc);
    if (!flag.empty()) P.remove_if_flagged(flag);
    for (std::size_t off = 0; off < in.size(); off += pb) P.add_packed(in.data() + off);
    migrated_ += static_cast<double>(in.size() / pb);
  }

  void build(ParticleStore<D>& P, double margin) override {
    const std::size_t n = P.n_owned(), pb = P.packed_bytes();
    send_.assign(size(), {});
    shift_.assign(size(), {});
    const double L = phi_ - plo_;
    // the ranks whose slab, widened by the margin, holds x (+ a period across a periodic face):
    // neighbours only, searched outwards; the ends of a periodic axis are its faces
    auto lower = [&](int q) { return q == 0 && periodic_ ? plo_ : cut_[q]; };
    auto upper = [&](int q) { return q == size() - 1 && periodic_ ? phi_ : cut_[q + 1]; };
    auto add = [&](std::size_t i, double x, double s, bool self) {
      for (int q = rank_ - 1; q >= 0 && x < upper(q) + margin; --q)
        if (x >= lower(q) - margin) { send_[q].push_back(static_cast<std::uint32_t>(i)); shift_[q].push_back(s); }
      for (int q = rank_ + 1; q < size() && x >= lower(q) - margin; ++q)
        if (x < upper(q) + margin) { send_[q].push_back(static_cast<std::uint32_t>(i)); shift_[q].push_back(s); }
      if (self && x >= lower(rank_) - margin && x < upper(rank_) + margin) {
        send_[rank_].push_back(static_cast<std::uint32_t>(i));
        shift_[rank_].push_back(s);
      }
    };
    for (std::size_t i = 0; i < n; ++i) {
      const double x = P.pos[i][axis_];
      add(i, x, 0.0, false);
      if (periodic_ && x > phi_ - margin) add(i, x - L, -L, true);  // its image past the lower face
      if (periodic_ && x < plo_ + margin) add(i, x + L, L, true);   // past the upper face
    }
    std::vector<std::vector<std::byte>> send(size());
    pack_all(P, send);
    const auto in = exchange_bytes(send, recv_);
    begin_ = P.size();
    for (std::size_t off = 0; off < in.size(); off += pb) P.add_remote_image(in.data() + off);
    end_ = P.size();
    count(send);
  }

  void refresh(ParticleStore<D>& P) override {
    const std::size_t pb = P.packed_bytes();
    std::vector<std::vector<std::byte>> send(size());
    pack_all(P, send);
    std::vector<int> rc;
    const auto in = exchange_bytes(send, rc);
    std::size_t i = begin_;
    for (std::size_t off = 0; off < in.size(); off += pb) P.unpack(i++, in.data() + off);
    count(send);
  }

  void refresh_column(const ParticleStore<D>&, std::byte* column, std::size_t width) override {
    std::vector<std::vector<std::byte>> send(size());
    for (int q = 0; q < size(); ++q) {
      send[q].resize(send_[q].size() * width);
      for (std::size_t k = 0; k < send_[q].size(); ++k)
        std::memcpy(send[q].data() + k * width, column + std::size_t(send_[q][k]) * width, width);
    }
    std::vector<int> rc;
    const auto in = exchange_bytes(send, rc);
    std::memcpy(column + begin_ * width, in.data(), in.size());
    count(send);
  }

  double bytes_sent() const { return bytes_; }
  double migrated() const { return migrated_; }
  long rebalances() const { return rebalances_; }
  /// Checked every kCheckEvery neighbour builds; new cuts above this ratio of the largest fluid
  /// count to the mean (the moved particles are one migration, like a step's).
  static constexpr long kCheckEvery = 50;
  static constexpr double kRebalanceAbove = 1.10;

 private:
  int axis_;
  std::vector<double> cut_;
  int rank_;
  std::vector<std::vector<std::uint32_t>> send_;  // owned particles each rank gets a copy of
  std::vector<std::vector<double>> shift_;        // and the period added to each copy's position (0: none)
  bool periodic_ = false;
  double plo_ = 0.0, phi_ = 0.0;
  /// The copies of send_, packed, their positions shifted across a periodic face where needed.
  void pack_all(const ParticleStore<D>& P, std::vector<std::vector<std::byte>>& send) const {
    const std::size_t pb = P.packed_bytes();
    for (int q = 0; q < size(); ++q) {
      send[q].resize(send_[q].size() * pb);
      for (std::size_t k = 0; k < send_[q].size(); ++k) {
        std::byte* out = send[q].data() + k * pb;
        P.pack(send_[q][k], out);
        if (shift_[q][k] != 0.0) {  // (the position is the packed particle's first field)
          double x;
          std::memcpy(&x, out + axis_ * sizeof(double), sizeof(double));
          x += shift_[q][k];
          std::memcpy(out + axis_ * sizeof(double), &x, sizeof(double));
        }
      }
    }
  }
  std::vector<int> recv_;
  std::size_t begin_ = 0, end_ = 0;
  double bytes_ = 0.0, migrated_ = 0.0;
  long builds_ = 0, rebalances_ = 0;
  void count(const std::vector<std::vector<std::byte>>& send) {
    for (const auto& b : send) bytes_ += static_cast<double>(b.size());
  }
};

}  // namespace

std::shared_ptr<const Communicator> world() {
  const char* n = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!n) n = std::getenv("PMI_SIZE");
  if (!n || std::atoi(n) <= 1) return std::make_shared<Communicator>();
  int init = 0;
  MPI_Initialized(&init);
  if (!init) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    std::atexit(finalise_mpi);
  }
  return std::make_shared<MpiCommunicator>();
}

template <int D>
void distribute(System<D>& S, std::shared_ptr<const Communicator> comm) {
  const int size = comm->size(), rank = comm->rank();
  auto& P = S.particles;
  P.clear_images();
  // the slab axis: the longest extent of all particles
  double lo[D], hi[D];
  for (int d = 0; d < D; ++d) { lo[d] = std::numeric_limits<double>::max(); hi[d] = -lo[d]; }
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    for (int d = 0; d < D; ++d) { lo[d] = std::min(lo[d], P.pos[i][d]); hi[d] = std::max(hi[d], P.pos[i][d]); }
  comm->min(lo, D);
  comm->max(hi, D);
  int axis = 0;
  for (int d = 1; d < D; ++d)
    if (hi[d] - lo[d] > hi[axis] - lo[axis]) axis = d;
  // cuts balancing the fluid particles (walls weigh nothing: the pair passes run over fluid, and
  // walls with no fluid near are skipped. 3D dam break, 395 k particles, 2 ranks: wall weight
  // 0 / 0.1 / 0.25 / 0.5 / 1 gave 6.0 / 6.4 / 7.2 / 8.3 / 9.3 s for 60 steps; one rank 10.9 s)
  const std::vector<double> cuts = balanced_cuts(P, axis, size, true);
  auto slabs = std::make_shared<Slabs<D>>(axis, cuts, rank);
  if (S.periodic.axis[axis]) {  // the slabs make the images across that axis's faces
    slabs->set_period(S.periodic.lo[axis], S.periodic.hi[axis]);
    S.periodic.imaged_elsewhere[axis] = true;
  }
  std::vector<char> flag(P.n_owned(), 0);
  for (std::size_t i = 0; i < P.n_owned(); ++i) flag[i] = slabs->owner(P.pos[i][axis]) != rank;
  P.remove_if_flagged(flag);
  S.ranks = slabs;
  S.comm = comm;
}

template <int D>
RankStats rank_stats(const System<D>& S, long steps) {
  RankStats r;
  const auto* sl = dynamic_cast<const Slabs<D>*>(S.ranks.get());
  if (!sl) return r;
  const auto& comm = *S.comm;
  const double n = static_cast<double>(S.particles.n_owned());
  r.imbalance = comm.max(n) / std::max(1.0, comm.sum(n) / comm.size());
  const double st = std::max(1L, steps);
  r.halo_bytes_per_step = comm.sum(sl->bytes_sent()) / comm.size() / st;
  r.migrated_per_step = comm.sum(sl->migrated()) / st;
  r.rebalances = sl->rebalances();
  const double nf = static_cast<double>(S.particles.count(Kind::Fluid));
  r.fluid_imbalance = comm.max(nf) / std::max(1.0, comm.sum(nf) / comm.size());
  return r;
}

void abort_ranks(const Communicator& comm, const std::string& message, int code) {
  fmt::print(stderr, "error (rank {} of {}): {}\nstopping every rank; the last snapshot written is the restart point\n",
             comm.rank(), comm.size(), message);
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // (MPI_Abort does not return)
}

template <int D>
void gather_particles(const System<D>& S, ParticleStore<D>& all) {
  const auto& P = S.particles;
  const std::size_t n = P.n_owned(), pb = P.packed_bytes();
  std::vector<std::byte> mine(n * pb);
  for (std::size_t i = 0; i < n; ++i) P.pack(i, mine.data() + i * pb);
  const int size = S.comm->size();
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(size), offsets(size);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  long long total = 0;
  for (int q = 0; q < size; ++q) {
    offsets[q] = static_cast<int>(total);
    total += counts[q];
  }
  if (total > std::numeric_limits<int>::max())
    throw std::runtime_error("snapshot of a distributed run: more than 2 GB of particles to gather on one rank");
  std::vector<std::byte> in(S.comm->root() ? static_cast<std::size_t>(total) : 0);
  MPI_Gatherv(mine.data(), count, MPI_BYTE, in.data(), counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
  all = ParticleStore<D>();
  if (!S.comm->root()) return;
  for (const auto& [name, f] : P.scalar_fields()) all.scalar(name);
  for (const auto& [name, f] : P.vector_fields()) all.vector(name);
  for (std::size_t off = 0; off < in.size(); off += pb) all.add_packed(in.data() + off);
  std::vector<std::uint32_t> perm(all.n_owned());
  for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<std::uint32_t>(i);
  std::sort(perm.begin(), perm.end(), [&](std::uint32_t a, std::uint32_t b) { return all.id[a] < all.id[b]; });
  all.permute(perm);
}

template void gather_particles<2>(const System<2>&, ParticleStore<2>&);
template void gather_particles<3>(const System<3>&, ParticleStore<3>&);
template void distribute<2>(System<2>&, std::shared_ptr<const Communicator>);
template void distribute<3>(System<3>&, std::shared_ptr<const Communicator>);
template RankStats rank_stats<2>(const System<2>&, long);
template RankStats rank_stats<3>(const System<3>&, long);

}  // namespace sph
