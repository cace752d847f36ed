// A kernel sum over volumes on the pair-pass seam (core/pair_pass.hpp): for every owned fluid particle a, a vector
// loop over its cell's candidates with their positions, their volumes V_b and (levels) their h_b in double columns.
// The passes that read nothing else of b share it: shifting's ∇C and ∇·r (physics/shifting.cpp), Grenier's Γ
// (physics/multiphase.cpp).
#pragma once
#include <cstdint>

#include "sphflume/core/pair_pass.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

/// body(a, xa0, xa1, xa2, ha, x0, x1, x2, vb, hb, npad) for every owned fluid particle a: its position relative to
/// the cell's origin (xa2 is xa1 in 2D), its h (levels; 0 otherwise), and its cell's candidates in columns: their
/// positions (x2 is x1 in 2D), volumes vb (vol(j) of candidate j; the padding's 0) and h_b (levels; the padding's
/// 1), npad of them. The body (its column parameters __restrict) runs its own vector loop, with a copy of the kernel
/// as a local (through a captured reference GCC gathers its constants lane by lane), and writes its sums for a.
template <int D, bool Lev, class Vol, class Body>
void volume_sweep(const System<D>& S, Vol&& vol, Body&& body) {
  const auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double* hs = Lev ? S.level_h() : nullptr;
  const Kind* kind = P.kind.data();
  const auto& cells = S.cells;
  const std::uint32_t* sorted = cells.sorted().data();
  enum : int { kVol = 3, kHs, kCols };
  auto needs = [&](std::size_t cell) {
    std::size_t m = 0;
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k)
      m += (sorted[k] < n && kind[sorted[k]] == Kind::Fluid) ? 1 : 0;
    return m;
  };
  sweep_cells<double>(cells, kCols, 8, needs, [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<double>& B) {
    const Vec<D> origin = P.pos[sorted[cells.cell_begin(cell)]];
    gather_columns<D, double>(st, B, P.pos.data(), origin, column(int(kVol), 0.0, vol),
                              only_if<Lev>(column(int(kHs), 1.0, [hs](std::size_t j) { return hs[j]; })));
    for (std::uint32_t q = cells.cell_begin(cell); q < cells.cell_end(cell); ++q) {
      const std::uint32_t a = sorted[q];
      if (a >= n || kind[a] != Kind::Fluid) continue;
      body(a, P.pos[a][0] - origin[0], P.pos[a][1] - origin[1], P.pos[a][D - 1] - origin[D - 1], Lev ? hs[a] : 0.0,
           B[0], B[1], B[D - 1], B[kVol], B[kHs], st.padded);
    }
    return std::uint64_t{0};  // (no pair count: nothing reads it)
  });
}

}  // namespace sph
