// Micro-benchmarks (Google Benchmark) of the hot paths on the 2D dam-break column: one WCSPH
// rates pass (all pair physics), the cell-list build, and one full time step per integrator.
// Counters: pairs/s (neighbour interactions per second) and particles/s.
// Run: build/bench/bench_rates [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <fmt/format.h>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/schemes/wcsph.hpp"

using namespace sph;

namespace {
struct Fixture {
  Case c;
  System<2> S;
  std::unique_ptr<WCSPH<2>> scheme;
  explicit Fixture(double dx, const char* integrator = "symplectic", const char* extra = "") {
    c = parse_case(fmt::format(R"(
dimension: 2
particles: {{dx: {}}}
fluid: {{density: 1000.0}}
walls: {{type: dummy, slip: free_slip}}
scheme: {{viscosity: artificial, alpha: 0.02, integrator: {}}}
geometry:
  - {{type: tank, min: [0.0, 0.0], max: [0.584, 0.73]}}
  - {{type: box, fill: fluid, min: [0.0, 0.0], max: [0.146, 0.292]}}
time: {{end: 1.0}}
{}
)", dx, integrator, extra), "bench");
    BuildReport rep;
    setup_system<2>(c, S, rep);  // the CLI's set-up: the walls with their surface vectors, scalars, force terms
    scheme = std::make_unique<WCSPH<2>>(c);
    scheme->initialise(S);
    for (int i = 0; i < 20; ++i) scheme->step(S, scheme->time_step(S));  // leave the lattice
  }
};

// dx giving ~5k, 20k, 80k fluid particles
const double kDx[] = {0.00292, 0.00146, 0.00073};

void BM_RatesPass(benchmark::State& st) {
  Fixture f(kDx[st.range(0)]);
  std::uint64_t pairs = 0;
  for (auto _ : st) {
    f.S.update_neighbours();
    f.scheme->rates(f.S);
    pairs += f.S.pairs_last_pass;
  }
  st.counters["pairs/s"] = benchmark::Counter(static_cast<double>(pairs), benchmark::Counter::kIsRate);
  st.counters["particles"] = static_cast<double>(f.S.particles.n_owned());
  st.counters["particles/s"] = benchmark::Counter(static_cast<double>(f.S.particles.n_owned()) * st.iterations(),
                                                  benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RatesPass)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

void BM_CellListBuild(benchmark::State& st) {
  Fixture f(kDx[st.range(0)]);
  for (auto _ : st) f.S.update_neighbours();
  st.counters["particles/s"] = benchmark::Counter(static_cast<double>(f.S.particles.size()) * st.iterations(),
                                                  benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CellListBuild)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

void BM_Step(benchmark::State& st, const char* integrator) {
  Fixture f(kDx[1], integrator);
  for (auto _ : st) f.scheme->step(f.S, f.scheme->time_step(f.S));
  st.counters["particle-steps/s"] = benchmark::Counter(static_cast<double>(f.S.particles.n_owned()) * st.iterations(),
                                                       benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_Step, symplectic, "symplectic")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Step, predictor_corrector, "predictor_corrector")->Unit(benchmark::kMillisecond);

// One transported scalar on the same column: its rates pass alone, and a full step with it
// (compare with BM_Step/symplectic for the scalar's share of a step).
constexpr const char* kScalar = R"(transport:
  scalars: [{name: c, diffusivity: 1.0e-6, initial: [{type: expression, expression: "z"}]}])";
void BM_ScalarRates(benchmark::State& st) {
  Fixture f(kDx[1], "symplectic", kScalar);
  f.S.update_neighbours();
  for (auto _ : st) f.S.transport->rates(f.S);
  st.counters["particles/s"] = benchmark::Counter(static_cast<double>(f.S.particles.n_owned()) * st.iterations(),
                                                  benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ScalarRates)->Unit(benchmark::kMillisecond);
void BM_StepWithScalar(benchmark::State& st) {
  Fixture f(kDx[1], "symplectic", kScalar);
  for (auto _ : st) f.scheme->step(f.S, f.scheme->time_step(f.S));
  st.counters["particle-steps/s"] = benchmark::Counter(static_cast<double>(f.S.particles.n_owned()) * st.iterations(),
                                                       benchmark::Counter::kIsRate);
}
BENCHMARK(BM_StepWithScalar)->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
