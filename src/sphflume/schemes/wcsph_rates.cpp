// The weakly-compressible scheme's rates pass (schemes/wcsph.hpp): the services in their order and the sweep of
// each particle over its cell's whole stencil (the fused single-precision pair loop: schemes/wcsph_rates_pass.hpp).
// ISPH's force pass is the same loop with the pressure switched off (SchemeConfig::pressure); the plain terms visit
// each fluid pair once instead (schemes/wcsph_rates_half.cpp), through the same pair terms.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "sphflume/core/pair_pass.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/schemes/wcsph_rates_pass.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/physics/turbulence.hpp"
#include "sphflume/schemes/wcsph.hpp"
#include "sphflume/schemes/wcsph_common.hpp"
#include "sphflume/schemes/wcsph_terms.hpp"

namespace sph {

template <int D>
template <class K>
void WCSPH<D>::pair_loop(System<D>& S, const K& ker, const double* fast) {
  // XSPH's smoothed velocity needs W(r) in every pair, turbulence the velocity gradient and
  // the stress divergence: each is compiled in only when it is on
  // porosity the SPHAM terms (volumes m/(φρ), porosity-weighted velocities)
  const bool turb = turb_.on();
  auto with_bool = [](bool b, auto&& f) {
    if (b) f(std::true_type{});
    else f(std::false_type{});
  };
  if (S.levels > 0 && !S.phase_eos.empty()) {  // resolution levels with several phases (no turbulence, porosity)
    with_bool(cfg_.xsph > 0.0, [&](auto xs) { this->template sweep<K, decltype(xs)::value, false, false, true, true, true>(S, ker, fast); });
  } else if (S.levels > 0) {  // resolution levels: per-pair h (setup refuses them with ISPH)
    with_bool(cfg_.xsph > 0.0, [&](auto xs) {
      with_bool(turb, [&](auto tu) {
        with_bool(static_cast<bool>(S.porous), [&](auto po) {
          this->template sweep<K, decltype(xs)::value, decltype(tu)::value, decltype(po)::value, false, true, true>(S, ker, fast);
        });
      });
    });
  } else if (!cfg_.pressure) {  // the forces alone (ISPH's prediction: no pressure, no XSPH, one phase)
    with_bool(turb, [&](auto tu) {
      with_bool(static_cast<bool>(S.porous), [&](auto po) {
        this->template sweep<K, false, decltype(tu)::value, decltype(po)::value, false, false>(S, ker, fast);
      });
    });
  } else if (!S.phase_eos.empty()) {  // several phases (setup refuses them with turbulence or porosity)
    with_bool(cfg_.xsph > 0.0, [&](auto xs) { this->template sweep<K, decltype(xs)::value, false, false, true>(S, ker, fast); });
  } else {
    with_bool(cfg_.xsph > 0.0, [&](auto xs) {
      with_bool(turb, [&](auto tu) {
        with_bool(static_cast<bool>(S.porous), [&](auto po) {
          this->template sweep<K, decltype(xs)::value, decltype(tu)::value, decltype(po)::value, false>(S, ker, fast);
        });
      });
    });
  }
  if (turb) turb_.update(S);
}

using namespace rates;  // (single precision: schemes/wcsph_terms.hpp)

template <int D>
template <class K, bool Xsph, bool Turb, bool Porous, bool Multi, bool Press, bool VarH>
void WCSPH<D>::sweep(System<D>& S, const K& ker, const double* fast) {
  auto& P = S.particles;
  RatesPass<D> q = rates_pass_of<D, K, Porous, Multi, VarH>(S, cfg_, ker);
  if constexpr (Turb) {
    for (int k = 0; k < Turbulence<D>::kStress; ++k) q.tau[k] = P.scalar(Turbulence<D>::stress_name(k)).data();
    q.grad = turb_.gradient(P.n_owned());
  }
  const std::size_t np = P.size();
  pack_rates<D, Turb, Porous, Multi, VarH>(q, np, pack_);
  const F32* pk = pack_.data();
  const auto& cells = S.cells;
  const std::uint32_t* __restrict sorted = cells.sorted().data();
  // a cell needs the loop when it holds owned particles that need rates (fluid; walls only when
  // dynamic); the others get zero rates here
  // (a multirate fast pass, fast: only the fast particles run, schemes/multirate.cpp; the others'
  // rates are restored after the pass)
  auto needs = [&](std::size_t cell) {
    std::size_t m = 0;  // the particles the pass runs
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k) {
      const std::uint32_t a = sorted[k];
      if (a >= q.n_owned) continue;
      if (q.runs(a) && (!fast || fast[a] != 0.0)) { ++m; continue; }
      q.acc[a] = Vec<D>{};
      q.drho[a] = 0.0;
    }
    return m;
  };
  S.pairs_last_pass = sweep_cells<F32>(cells, NCOL, 16, needs,
                                       [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<F32>& B) {
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    const Vec<D> origin = q.pos[sorted[c0k]];
    gather_rates<D, Turb, Porous, Multi, VarH>(q, pk, np, st, B, origin);
    const RatesColumns c = rates_columns<D>(B, st.padded);
    const K kl = ker;
    std::uint64_t pairs = 0;
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t a = sorted[k];
      if (a < q.n_owned && q.runs(a) && (VarH ? !fast || fast[a] != 0.0 : true))
        pairs += rates_particle<D, K, Xsph, Turb, Porous, Multi, Press, VarH>(q, kl, c, origin, a);
    }
    return pairs;
  });
}

template <int D>
void WCSPH<D>::rates_pass(System<D>& S, bool fast_only, bool smooth_h) {
  if (cfg_.frozen) {  // only the scalars move
    if (S.transport) S.transport->rates(S);
    return;
  }
  if (S.before_rates) S.before_rates(S);
  // a multirate pass of the fast particles: the slow ones keep the rates of their stage (restored
  // below)
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  // (the walls, force terms and drag below write every particle's; the copies and the put-back run on the threads,
  // into buffers kept between passes)
  Vec<D>* xs = fast_only && cfg_.xsph > 0.0 ? P.vector(field::xsph).data() : nullptr;
  double* kr = fast_only && S.porous ? P.scalar(field::drag_rate).data() : nullptr;
  double* im = fast_only && S.porous ? P.scalar(field::inertia).data() : nullptr;
  auto& kept = kept_;
  if (fast_only) {
    kept.acc.resize(n);
    kept.drho.resize(n);
    kept.xs.resize(xs ? n : 0);
    kept.kr.resize(kr ? n : 0);
    kept.im.resize(kr ? n : 0);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      kept.acc[i] = P.acc[i];
      kept.drho[i] = P.drho[i];
      if (xs) kept.xs[i] = xs[i];
      if (kr) { kept.kr[i] = kr[i]; kept.im[i] = im[i]; }
    }
  }
  if (S.porous) S.porous->update(S);  // φ at the current positions (before the pair loop reads it)
  if (S.grenier) grenier_gamma(S);  // Γ of Grenier's pressure gradient
  // resolution levels: h at the particles' places (the multirate integrator sets it at the start of its step and
  // every pass of the step keeps it: schemes/multirate.cpp)
  if (S.resolution && smooth_h && !fast_only) S.resolution->smooth_h(S);
  const double* near_fast = fast_only ? P.scalar(field::fast.name).data() : nullptr;  // (the walls near the fast ones)
  S.walls->prepare(S, near_fast);
  // the plain terms visit each fluid pair once (half stencils: schemes/wcsph_rates_half.cpp; with levels on one cell
  // grid per level or on level 0's); the other models and a multirate fast pass run each particle over its whole
  // stencil
  if (cfg_.half_sweep && cfg_.pressure && S.phase_eos.empty() && !turb_.on() && !S.porous && !near_fast &&
      !S.walls->evolves_density() && (S.levels == 0 ? S.cells.uniform_stencil() : S.cells.pair_once()))
    half_sweep(S);
  else
    S.with_kernel([&](const auto& K) { this->pair_loop(S, K, near_fast); });
  S.walls->add_forces(S, near_fast);
  for (auto& f : S.forces) f->add(S);
  if (S.porous) S.porous->drag(S);  // the drag rate the integrator applies point-implicitly
  // after the pair loop (the advection variants use drho); a multirate fast pass leaves the scalars' rates alone (the
  // scalars take the slow step, schemes/multirate.cpp)
  if (S.transport && !fast_only) S.transport->rates(S);
  if (fast_only) {
    const double* fast = P.scalar(field::fast.name).data();
    xs = xs ? P.vector(field::xsph).data() : nullptr;  // (the passes above may have grown the store's fields)
    kr = kr ? P.scalar(field::drag_rate).data() : nullptr;
    im = kr ? P.scalar(field::inertia).data() : nullptr;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (fast[i] != 0.0) continue;
      P.acc[i] = kept.acc[i];
      P.drho[i] = kept.drho[i];
      if (xs) xs[i] = kept.xs[i];
      if (kr) { kr[i] = kept.kr[i]; im[i] = kept.im[i]; }
    }
  }
  double amax = 0.0;
#pragma omp parallel for schedule(static) reduction(max : amax)
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid) amax = std::max(amax, dot(P.acc[i], P.acc[i]));
  max_acc_ = std::sqrt(amax);
  if (!std::isfinite(max_acc_)) check_finite(S);
}

template void WCSPH<2>::rates_pass(System<2>&, bool, bool);
template void WCSPH<3>::rates_pass(System<3>&, bool, bool);

}  // namespace sph
