// The dual-criteria Riemann scheme (`scheme: {type: wcsph, integrator: dual}`): Zhang, Hu &
// Adams (2017, J. Comput. Phys. 335) low-dissipation Riemann-solver WCSPH with the dual-criteria
// time stepping of Zhang, Zhang & Hu (2020, J. Comput. Phys. 404), the scheme of SPHinXsys's
// fluid dynamics. Every advection step the density is re-initialised by summation; inside it,
// acoustic steps of position Verlet with two light pair passes (dual_passes.cpp). It carries
// dummy walls, one inviscid phase and no other model yet (dual_check, schemes/wcsph_options.cpp);
// resolution levels with each pair's kernel at h_ab (docs/numerics.md §14).
// It shares the equation of state, the time-step rule and the finite check with WCSPH
// (schemes/wcsph_common.hpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/schemes/scheme.hpp"

namespace sph {

template <int D>
class DualWCSPH final : public Scheme<D> {
 public:
  explicit DualWCSPH(const Case& c) : cfg_(c.scheme) {}
  const char* name() const override { return "wcsph"; }
  const char* integrator() const override { return "dual"; }
  void initialise(System<D>& S) override;
  double time_step(const System<D>& S) const override;
  void step(System<D>& S, double dt) override;
  bool needs_wall_surface() const override { return true; }  // Riemann dissipation at walls
  int passes_per_step() const override { return 2; }
  std::string distributed_refusal() const override {
    return cfg_.pairs_per_advection
               ? "scheme.pairs: advection (the kept pairs hold one process's store indices; pairs: acoustic runs on ranks)"
               : "";
  }
  std::size_t bytes() const override {  // the packed columns and the kept pairs
    return pack_.capacity() * sizeof(float) + kept_.bytes();
  }
  std::map<std::string, double> state() const override {
    return {{"max_acc", max_acc_}, {"advection_left", adv_left_}};
  }
  void restore(const std::map<std::string, double>& s) override {
    if (auto it = s.find("max_acc"); it != s.end()) max_acc_ = it->second;
    if (auto it = s.find("advection_left"); it != s.end()) adv_left_ = it->second;
  }

 private:
  /// One pair pass: 0 pressure (A), 1 continuity (B), 2 density summation (dual_passes.cpp).
  void riemann_pass(System<D>& S, int pass);
  template <class K, int Pass, bool VarH>
  void riemann_sweep(System<D>& S, const K& kernel);
  void reinit_density(System<D>& S);

  /// `pairs: advection` (SPHinXsys's configuration): each fluid particle's pairs found at the start of an advection
  /// step, with the kernel's W'(r) and the direction e = (x_a − x_b)/r there, kept through its acoustic steps
  /// (dual_pairs.cpp). Rows of a multiple of the lanes (padding: the particle itself with W' = 0), in store order.
  struct KeptPairs {
    std::vector<std::uint32_t> begin, mid, end;  // each store index's row: fluid partners [begin, mid), walls [mid, end)
    std::vector<std::uint32_t> j;           // the partner's store index
    std::vector<float> dw;                  // W'(r_ab) (≤ 0)
    std::vector<float> e;                   // D components per pair
    std::vector<std::uint32_t> ids;         // the store's ids when they were found (to follow a re-sort)
    std::uint64_t layout = 0;               // the store's layout then
    std::size_t cap = 0;                    // each thread's region of j, dw, e (the rows of its cells)
    bool valid = false;
    WallPairs walls;                        // the same pairs from the walls' side, for their extrapolation
    std::size_t bytes() const {
      return (begin.capacity() + mid.capacity() + end.capacity() + j.capacity() + ids.capacity()) * 4 +
             (dw.capacity() + e.capacity()) * 4 + walls.bytes();
    }
  };
  /// density: also the summation density of the advection step's start (Σ W over the pairs found, scheme.density_reinit)
  void find_pairs(System<D>& S, bool density);
  void follow_resort(System<D>& S);
  template <class K, int Pass>
  void kept_pass(System<D>& S, const K& kernel);
  void kept_pass_dispatch(System<D>& S, int pass);
  KeptPairs kept_;

  SchemeConfig cfg_;
  double max_acc_ = 0.0;
  double adv_left_ = 0.0;  // what is left of the current advection step
  double sigma0_ = 0.0;    // Σ W of a full lattice (the summation density's reference)
  std::vector<float> pack_;  // the per-particle columns of the current pass (riemann_sweep)
};

}  // namespace sph
