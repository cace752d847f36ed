// Periodic boundaries: a halo layer (core/halo.hpp) of image particles in the store's image
// range, and wrapping of owned particles that cross a periodic face (its migration).
#pragma once
#include <cstring>
#include <vector>

#include "sphflume/core/halo.hpp"
#include "sphflume/core/particles.hpp"

namespace sph {

template <int D>
struct Periodic final : Halo<D> {
  using V = Vec<D>;
  bool axis[D]{};
  V lo{}, hi{};
  /// Periodic axes whose images another layer makes (the MPI slabs, along their own axis):
  /// wrapped here, imaged there.
  bool imaged_elsewhere[D]{};

  bool any() const {
    for (int d = 0; d < D; ++d) if (axis[d]) return true;
    return false;
  }

  // --- the halo layer ---
  const char* name() const override { return "periodic"; }
  bool active() const override {
    for (int d = 0; d < D; ++d) if (axis[d] && !imaged_elsewhere[d]) return true;
    return false;
  }
  /// (nothing: the schemes wrap at the end of each step, wrap(), because the two-stage
  /// integrators keep the start-of-step positions x0 in the unwrapped frame until then)
  void migrate(ParticleStore<D>&) override {}
  void build(ParticleStore<D>& P, double margin) override {
    begin_ = P.size();
    build_images(P, margin);
    end_ = P.size();
  }
  void refresh(ParticleStore<D>& P) override { P.refresh_images(begin_, end_); }
  void refresh_column(const ParticleStore<D>& P, std::byte* column, std::size_t width) override {
    const std::size_t n = P.n_owned();
    for (std::size_t i = begin_; i < end_; ++i)
      std::memcpy(column + i * width, column + std::size_t(P.image_source[i - n]) * width, width);
  }
  double period(int d) const { return hi[d] - lo[d]; }

  /// Add an image for every particle within `margin` of a periodic face (and of edges/corners
  /// when several axes are periodic): the owned ones, and the copies earlier layers made (another
  /// rank's particle next to a periodic face this rank also touches).
  void build_images(ParticleStore<D>& P, double margin) const {
    if (!any()) return;
    const std::size_t n = P.size();
    for (std::size_t i = 0; i < n; ++i) {
      // each axis: -1 (near lo, image shifted by +L), +1 (near hi, shifted by -L), 0
      int side[D];
      bool near = false;
      for (int d = 0; d < D; ++d) {
        side[d] = 0;
        if (!axis[d] || imaged_elsewhere[d]) continue;
        if (P.pos[i][d] < lo[d] + margin) side[d] = -1;
        else if (P.pos[i][d] > hi[d] - margin) side[d] = 1;
        near |= side[d] != 0;
      }
      if (!near) continue;
      // all non-empty subsets of the near axes
      for (int mask = 1; mask < (1 << D); ++mask) {
        bool ok = true;
        V shift{};
        for (int d = 0; d < D; ++d) {
          if (!(mask & (1 << d))) continue;
          if (side[d] == 0) { ok = false; break; }
          shift[d] = -side[d] * period(d);
        }
        if (ok) P.add_image(static_cast<std::uint32_t>(i), shift);
      }
    }
  }

  /// Bring owned particles that crossed a periodic face back into [lo, hi).
  void wrap(ParticleStore<D>& P) const {
    if (!any()) return;
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      for (int d = 0; d < D; ++d) {
        if (!axis[d]) continue;
        if (P.pos[i][d] < lo[d]) P.pos[i][d] += period(d);
        else if (P.pos[i][d] >= hi[d]) P.pos[i][d] -= period(d);
      }
  }

 private:
  std::size_t begin_ = 0, end_ = 0;  // this layer's images in the store
};

}  // namespace sph
