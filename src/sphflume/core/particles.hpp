// Particle storage: structure of arrays, every kind of particle (fluid, wall, inflow, outflow)
// in one store, told apart by a kind tag.
//
// Layout: indices [0, n_owned) are the particles this process owns and integrates; indices
// [n_owned, size()) are image copies made by the halo layers (core/halo.hpp: periodic images,
// MPI halo copies), each with the index of the owned particle it copies in `image_source`
// (kRemote: a copy of another rank's particle). Images are rebuilt before every neighbour pass
// and never integrated.
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphflume/core/fields.hpp"
#include "sphflume/core/vec.hpp"

namespace sph {

enum class Kind : std::uint8_t { Fluid = 0, Wall = 1, Inflow = 2, Outflow = 3 };
inline constexpr int kKindCount = 4;

/// Particles that carry water: fluid, and the inflow/outflow particles of open boundaries, whose
/// state is imposed instead of integrated. They are the sources of every fluid-side sum.
inline bool fluid_like(Kind k) { return k == Kind::Fluid || k == Kind::Inflow || k == Kind::Outflow; }

inline const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Fluid: return "fluid";
    case Kind::Wall: return "wall";
    case Kind::Inflow: return "inflow";
    case Kind::Outflow: return "outflow";
  }
  return "?";
}

template <int D>
class ParticleStore {
 public:
  using V = Vec<D>;
  // --- state (integrated) ---
  std::vector<V> pos, vel;
  std::vector<double> rho;
  // --- derived / constant ---
  std::vector<double> p, mass;
  std::vector<Kind> kind;
  std::vector<std::uint32_t> id;
  // --- rates, filled by the scheme each evaluation ---
  std::vector<V> acc;
  std::vector<double> drho;
  // --- images ---
  std::vector<std::uint32_t> image_source;  // size() - n_owned entries
  static constexpr std::uint32_t kRemote = 0xffffffffu;  // image_source of another rank's particle

  std::size_t size() const { return pos.size(); }
  std::size_t n_owned() const { return n_owned_; }
  /// A stamp of the owned particles' order, new (unique in the process) whenever particles are
  /// added, removed or reordered through this class: a cell list binned for one stamp may
  /// re-place only the particles that moved (CellList::build's in_order). Code that reorders
  /// the fields directly must call touch().
  std::uint64_t layout() const { return layout_; }
  void touch() { layout_ = next_stamp(); }

  /// Append one owned particle (only valid while there are no images).
  void add(const V& x, const V& v, double density, double m, Kind k) {
    pos.push_back(x);
    vel.push_back(v);
    rho.push_back(density);
    p.push_back(0.0);
    mass.push_back(m);
    kind.push_back(k);
    id.push_back(static_cast<std::uint32_t>(id.size()));
    acc.push_back(V{});
    drho.push_back(0.0);
    for (auto& [name, f] : scalar_fields_) f.push_back(0.0);
    for (auto& [name, f] : vector_fields_) f.push_back(V{});
    n_owned_ = pos.size();
    touch();
  }

  /// Append a copy of owned particle s, every field (only valid while there are no images);
  /// returns the new index.
  std::size_t add_copy(std::size_t s) {
    const std::size_t d = size();
    resize_all(d + 1);
    copy_particle(s, d);
    n_owned_ = size();
    touch();
    return d;
  }

  /// Particle d's extra fields (scalar and vector) set to the w-weighted means of particles
  /// src[0..n) (Σ w = 1); the core fields are the caller's.
  void mean_extra_fields(std::size_t d, const std::size_t* src, const double* w, std::size_t n) {
    for (auto& [k, f] : scalar_fields_) {
      double s = 0.0;
      for (std::size_t j = 0; j < n; ++j) s += w[j] * f[src[j]];
      f[d] = s;
    }
    for (auto& [k, f] : vector_fields_) {
      V s{};
      for (std::size_t j = 0; j < n; ++j) s += w[j] * f[src[j]];
      f[d] = s;
    }
  }

  /// Extra per-particle scalar field (e.g. a concentration, porosity). Created on first use;
  /// kept consistent through add/reorder/images like the core fields.
  std::vector<double>& scalar(const std::string& name) {
    auto it = scalar_fields_.find(name);
    if (it == scalar_fields_.end()) it = scalar_fields_.emplace(name, std::vector<double>(size(), 0.0)).first;
    return it->second;
  }
  std::vector<V>& vector(const std::string& name) {
    auto it = vector_fields_.find(name);
    if (it == vector_fields_.end()) it = vector_fields_.emplace(name, std::vector<V>(size(), V{})).first;
    return it->second;
  }
  bool has_scalar(const std::string& name) const { return scalar_fields_.count(name) != 0; }
  /// Read-only lookup: null when the field does not exist.
  const std::vector<double>* find_scalar(const std::string& name) const {
    auto it = scalar_fields_.find(name);
    return it == scalar_fields_.end() ? nullptr : &it->second;
  }
  const std::vector<V>* find_vector(const std::string& name) const {
    auto it = vector_fields_.find(name);
    return it == vector_fields_.end() ? nullptr : &it->second;
  }
  /// The engine's own fields by their typed handles (core/fields.hpp): a misspelt handle does
  /// not compile. The string forms above serve fields named at run time (a transported scalar,
  /// a stress component) and must not be called with a literal of an engine field.
  std::vector<double>& scalar(ScalarField f) { return scalar(std::string(f.name)); }
  std::vector<V>& vector(VectorField f) { return vector(std::string(f.name)); }
  bool has(ScalarField f) const { return scalar_fields_.count(f.name) != 0; }
  bool has(VectorField f) const { return vector_fields_.count(f.name) != 0; }
  const std::vector<double>* find(ScalarField f) const { return find_scalar(f.name); }
  const std::vector<V>* find(VectorField f) const { return find_vector(f.name); }
  /// A field that must exist (made at set-up): std::logic_error naming it otherwise.
  const std::vector<double>& require(ScalarField f) const {
    if (const auto* p = find(f)) return *p;
    throw std::logic_error(std::string("particle field '") + f.name + "' was not created at set-up");
  }
  const std::vector<V>& require(VectorField f) const {
    if (const auto* p = find(f)) return *p;
    throw std::logic_error(std::string("particle field '") + f.name + "' was not created at set-up");
  }
  std::vector<double>& require(ScalarField f) { return const_cast<std::vector<double>&>(static_cast<const ParticleStore&>(*this).require(f)); }
  std::vector<V>& require(VectorField f) { return const_cast<std::vector<V>&>(static_cast<const ParticleStore&>(*this).require(f)); }
  const std::map<std::string, std::vector<double>>& scalar_fields() const { return scalar_fields_; }
  const std::map<std::string, std::vector<V>>& vector_fields() const { return vector_fields_; }

  /// Drop all images, keeping the owned particles.
  void clear_images() { resize_all(n_owned_); image_source.clear(); image_shift_.clear(); }

  /// Append an image of owned particle `src`, displaced by `shift`.
  void add_image(std::uint32_t src, const V& shift) {
    const std::size_t i = size();
    resize_all(i + 1);
    copy_particle(src, i);
    pos[i] += shift;
    image_source.push_back(src);
    image_shift_.push_back(shift);
  }

  /// Refresh the fields of images [begin, end) (store indices) from their owned sources,
  /// keeping each image's displacement.
  void refresh_images(std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t k = i - n_owned_;
      copy_particle(image_source[k], i);
      pos[i] += image_shift_[k];
    }
  }

  // --- whole particles as bytes (the MPI halo and migration; every field, in a fixed order) ---
  /// Bytes of one packed particle: the core fields, then the named fields in name order.
  std::size_t packed_bytes() const {
    return 4 * sizeof(V) + 4 * sizeof(double) + sizeof(Kind) + sizeof(std::uint32_t) + scalar_fields_.size() * sizeof(double) +
           vector_fields_.size() * sizeof(V);
  }
  void pack(std::size_t i, std::byte* out) const {
    auto put = [&](const auto& v) { std::memcpy(out, &v, sizeof(v)); out += sizeof(v); };
    put(pos[i]); put(vel[i]); put(acc[i]); put(rho[i]); put(p[i]); put(mass[i]); put(drho[i]); put(kind[i]); put(id[i]);
    for (const auto& [k, f] : scalar_fields_) put(f[i]);
    for (const auto& [k, f] : vector_fields_) put(f[i]);
    // (the image shift is not sent: a packed particle is always at its owner's position)
  }
  /// Overwrite particle i (owned or image) with a packed one.
  void unpack(std::size_t i, const std::byte* in) {
    auto get = [&](auto& v) { std::memcpy(&v, in, sizeof(v)); in += sizeof(v); };
    get(pos[i]); get(vel[i]); get(acc[i]); get(rho[i]); get(p[i]); get(mass[i]); get(drho[i]); get(kind[i]); get(id[i]);
    for (auto& [k, f] : scalar_fields_) get(f[i]);
    for (auto& [k, f] : vector_fields_) get(f[i]);
  }
  /// Append a packed particle as owned (no images may exist).
  void add_packed(const std::byte* in) {
    if (size() != n_owned_) throw std::logic_error("ParticleStore::add_packed: images exist");
    resize_all(n_owned_ + 1);
    unpack(n_owned_, in);
    ++n_owned_;
    touch();
  }
  /// Append a packed particle of another rank as an image (image_source kRemote).
  void add_remote_image(const std::byte* in) {
    const std::size_t i = size();
    resize_all(i + 1);
    unpack(i, in);
    image_source.push_back(kRemote);
    image_shift_.push_back(V{});
  }

  /// Reorder owned particles: new index i holds old particle perm[i]. Requires no images.
  /// The permutation's cycles are found once and applied to every field in place, touching
  /// only the particles that move (after the first sort, few change cell between steps).
  void permute(const std::vector<std::uint32_t>& perm) {
    if (perm.size() != n_owned_ || size() != n_owned_)
      throw std::logic_error("ParticleStore::permute: needs a full permutation of the owned particles and no images");
    touch();
    find_cycles(perm);
    if (cycles_.empty()) return;
    // the fields are independent: one per thread at a time (the same result for any count)
    const std::size_t nf = list_fields();
#pragma omp parallel for schedule(dynamic, 1) if (cycles_.size() > 2048)
    for (std::size_t f = 0; f < nf; ++f) field_at(f, [&](auto& v) { cycle(v); });
    // the first sort moves nearly every particle, later ones fewer: do not keep a big list
    // between steps (`cycles_ = {}` would keep the capacity: it assigns an empty initializer list)
    if (cycles_.capacity() > n_owned_ / 16) std::vector<std::uint32_t>().swap(cycles_);
  }

  /// The same as permute(perm) for a perm that keeps all but m particles in their order (a cell
  /// list's update: CellList::moved()): `left` the movers' old indices ascending, `arrive` their
  /// old indices then their new ones, in ascending new index. The movers are kept aside, each
  /// run of the others is moved once (those moving to the front first, in ascending order, then
  /// those moving back, descending: since the others keep their order, no run overwrites one
  /// that is still to move), and the movers are put in their places: block copies instead of
  /// cycles through most of the store.
  void permute_runs(std::size_t m, const std::uint32_t* left, const std::uint32_t* arrive) {
    if (size() != n_owned_) throw std::logic_error("ParticleStore::permute_runs: images exist");
    touch();
    if (m == 0) return;
    const std::uint32_t* from = arrive;
    const std::uint32_t* to = arrive + m;
    const std::size_t n = n_owned_;
    runs_.clear();  // (new index, old index, length) of each run of the others
    for (std::size_t k = 0, i = 0, a = 0, l = 0; k < n;) {
      if (a < m && to[a] == k) { ++k; ++a; continue; }     // a mover's new place
      if (l < m && left[l] == i) { ++i; ++l; continue; }   // a mover's old place
      std::size_t len = n - k;
      if (a < m) len = std::min<std::size_t>(len, to[a] - k);
      if (l < m) len = std::min<std::size_t>(len, left[l] - i);
      runs_.push_back({static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(len)});
      k += len;
      i += len;
    }
    const std::size_t nf = list_fields();
    const std::size_t nr = runs_.size();
#pragma omp parallel for schedule(dynamic, 1) if (n > 4096)
    for (std::size_t f = 0; f < nf; ++f)
      field_at(f, [&](auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        std::vector<T> aside(m);
        for (std::size_t j = 0; j < m; ++j) aside[j] = v[from[j]];
        T* d = v.data();
        for (std::size_t r = 0; r < nr; ++r)
          if (runs_[r][0] < runs_[r][1]) std::copy(d + runs_[r][1], d + runs_[r][1] + runs_[r][2], d + runs_[r][0]);
        for (std::size_t r = nr; r-- > 0;)
          if (runs_[r][0] > runs_[r][1]) std::copy_backward(d + runs_[r][1], d + runs_[r][1] + runs_[r][2], d + runs_[r][0] + runs_[r][2]);
        for (std::size_t j = 0; j < m; ++j) v[to[j]] = aside[j];
      });
    if (runs_.capacity() > n / 256 + 512) std::vector<std::array<std::uint32_t, 3>>().swap(runs_);
  }

  /// Room for n particles in every field (before adding them one by one: growing by doubling held up to twice the
  /// store while it copied).
  void reserve(std::size_t n) {
    pos.reserve(n); vel.reserve(n); rho.reserve(n); p.reserve(n); mass.reserve(n);
    kind.reserve(n); id.reserve(n); acc.reserve(n); drho.reserve(n);
    for (auto& [k, f] : scalar_fields_) f.reserve(n);
    for (auto& [k, f] : vector_fields_) f.reserve(n);
  }

  /// Release spare capacity (after the particles are created one by one).
  void shrink_to_fit() {
    pos.shrink_to_fit(); vel.shrink_to_fit(); rho.shrink_to_fit(); p.shrink_to_fit(); mass.shrink_to_fit();
    kind.shrink_to_fit(); id.shrink_to_fit(); acc.shrink_to_fit(); drho.shrink_to_fit();
    for (auto& [k, f] : scalar_fields_) f.shrink_to_fit();
    for (auto& [k, f] : vector_fields_) f.shrink_to_fit();
  }

  /// Remove owned particles whose flag is set (requires no images). Returns how many.
  std::size_t remove_if_flagged(const std::vector<char>& flag) {
    std::vector<std::uint32_t> keep;
    keep.reserve(n_owned_);
    for (std::uint32_t i = 0; i < n_owned_; ++i) if (!flag[i]) keep.push_back(i);
    const std::size_t removed = n_owned_ - keep.size();
    if (removed == 0) return 0;
    permute_partial(keep);
    return removed;
  }

  /// Bytes held by per-particle arrays, per owned particle (capacity, so what is really held).
  std::size_t bytes() const {
    std::size_t b = cap_bytes(pos) + cap_bytes(vel) + cap_bytes(rho) + cap_bytes(p) + cap_bytes(mass) +
                    cap_bytes(kind) + cap_bytes(id) + cap_bytes(acc) + cap_bytes(drho) + cap_bytes(image_source) +
                    cap_bytes(image_shift_) + scratch_.capacity() / 8 + cap_bytes(cycles_) + cap_bytes(runs_);
    for (auto& [n, f] : scalar_fields_) b += cap_bytes(f);
    for (auto& [n, f] : vector_fields_) b += cap_bytes(f);
    return b;
  }

  std::size_t count(Kind k) const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < n_owned_; ++i) n += (kind[i] == k);
    return n;
  }

 private:
  std::size_t n_owned_ = 0;
  std::uint64_t layout_ = next_stamp();
  std::map<std::string, std::vector<double>> scalar_fields_;
  std::map<std::string, std::vector<V>> vector_fields_;
  std::vector<V> image_shift_;
  std::vector<bool> scratch_;  // visited marks (1 bit per particle)
  std::vector<std::uint32_t> cycles_;
  std::vector<std::vector<double>*> sf_;  // permute's list of the named fields (kept: no allocation per sort)
  std::vector<std::vector<V>*> vf_;

  std::vector<std::array<std::uint32_t, 3>> runs_;  // permute_runs' runs (kept: no allocation per sort)

  template <class T>
  static std::size_t cap_bytes(const std::vector<T>& v) { return v.capacity() * sizeof(T); }

  /// The named fields listed for field_at; returns the number of fields (9 core + named).
  std::size_t list_fields() {
    sf_.clear();
    vf_.clear();
    for (auto& [n, f] : scalar_fields_) sf_.push_back(&f);
    for (auto& [n, f] : vector_fields_) vf_.push_back(&f);
    return 9 + sf_.size() + vf_.size();
  }
  /// fn(field f) for f < list_fields(): the core fields, then the named ones.
  template <class Fn>
  void field_at(std::size_t f, Fn&& fn) {
    switch (f) {
      case 0: fn(pos); break;
      case 1: fn(vel); break;
      case 2: fn(rho); break;
      case 3: fn(p); break;
      case 4: fn(mass); break;
      case 5: fn(kind); break;
      case 6: fn(id); break;
      case 7: fn(acc); break;
      case 8: fn(drho); break;
      default:
        if (f - 9 < sf_.size()) fn(*sf_[f - 9]);
        else fn(*vf_[f - 9 - sf_.size()]);
    }
  }

  void resize_all(std::size_t n) {
    pos.resize(n); vel.resize(n); rho.resize(n); p.resize(n); mass.resize(n); kind.resize(n); id.resize(n);
    acc.resize(n); drho.resize(n);
    for (auto& [k, f] : scalar_fields_) f.resize(n);
    for (auto& [k, f] : vector_fields_) f.resize(n);
  }

  void copy_particle(std::size_t s, std::size_t d) {
    pos[d] = pos[s]; vel[d] = vel[s]; rho[d] = rho[s]; p[d] = p[s]; mass[d] = mass[s]; kind[d] = kind[s];
    id[d] = id[s]; acc[d] = acc[s]; drho[d] = drho[s];
    for (auto& [k, f] : scalar_fields_) f[d] = f[s];
    for (auto& [k, f] : vector_fields_) f[d] = f[s];
  }

  /// Removal: v[i] <- v[keep[i]] with keep increasing, so a forward compaction is safe.
  template <class T>
  void compact(std::vector<T>& v, const std::vector<std::uint32_t>& keep) {
    const std::size_t n = keep.size();
    for (std::size_t i = 0; i < n; ++i) v[i] = v[keep[i]];
    v.resize(n);
  }
  void compact_fields(const std::vector<std::uint32_t>& keep) {
    compact(pos, keep); compact(vel, keep); compact(rho, keep); compact(p, keep); compact(mass, keep);
    compact(kind, keep); compact(id, keep); compact(acc, keep); compact(drho, keep);
    for (auto& [n, f] : scalar_fields_) compact(f, keep);
    for (auto& [n, f] : vector_fields_) compact(f, keep);
  }
  /// cycles_ holds every non-trivial cycle (i0, perm[i0], perm[perm[i0]], ...) back to back,
  /// the first index of each with kCycleStart set (no separate array of lengths: a sort that
  /// moves every particle would need 4 more bytes per particle for it).
  static constexpr std::uint32_t kCycleStart = 0x80000000u;
  void find_cycles(const std::vector<std::uint32_t>& perm) {
    cycles_.clear();
    const std::size_t n = perm.size();
    if (n >= kCycleStart) throw std::length_error("ParticleStore::permute: more than 2^31 particles in one process");
    scratch_.assign(n, false);
    for (std::size_t start = 0; start < n; ++start) {
      if (scratch_[start] || perm[start] == start) continue;
      std::uint32_t mark = kCycleStart;
      for (std::size_t i = start; !scratch_[i]; i = perm[i]) {
        scratch_[i] = true;
        cycles_.push_back(static_cast<std::uint32_t>(i) | mark);
        mark = 0;
      }
    }
  }
  template <class T>
  void cycle(std::vector<T>& v) const {
    const std::uint32_t* c = cycles_.data();
    const std::size_t m = cycles_.size();
    for (std::size_t s = 0; s < m;) {
      std::size_t e = s + 1;
      while (e < m && !(c[e] & kCycleStart)) ++e;
      const std::uint32_t i0 = c[s] & ~kCycleStart;
      const T first = v[i0];
      std::uint32_t dst = i0;
      for (std::size_t j = s + 1; j < e; ++j) { v[dst] = v[c[j]]; dst = c[j]; }
      v[dst] = first;
      s = e;
    }
  }
  void permute_partial(const std::vector<std::uint32_t>& keep) {
    compact_fields(keep);
    n_owned_ = keep.size();
    touch();
  }
  static std::uint64_t next_stamp() {
    static std::atomic<std::uint64_t> counter{0};
    return ++counter;
  }
};

}  // namespace sph
