// Benchmark (not a test): the exact element Jacobian of the Newtonian flow kernel (21 local
// unknowns) over all elements of mesh M2's fluid part, with Eigen's
// AutoDiffScalar<Matrix<double, 21, 1>> (the type core/AutoDiff.hpp uses) and with a small
// hand-written dual type (value + Eigen::Array of derivatives, no expression templates). The
// project would switch to the hand-written type only if this showed it at least 2x faster.
#include <benchmark/benchmark.h>

#include "core/KernelTerm.hpp"
#include "problems/channel/ChannelProblem.hpp"
#include "problems/kernels/NewtonianFlowKernel.hpp"

using namespace keller;

namespace {

// The hand-written alternative: every operation returns a new value and derivative array.
template <int N>
struct HandDual {
  using A = Eigen::Array<double, N, 1>;
  double v = 0;
  A d = A::Zero();
  HandDual() = default;
  HandDual(double x) : v(x) {}  // NOLINT: constants promote implicitly, as with AutoDiffScalar
  HandDual(double x, const A& dx) : v(x), d(dx) {}
  HandDual& operator+=(const HandDual& o) {
    v += o.v;
    d += o.d;
    return *this;
  }
  HandDual& operator-=(const HandDual& o) {
    v -= o.v;
    d -= o.d;
    return *this;
  }
  friend HandDual operator+(const HandDual& a, const HandDual& b) { return {a.v + b.v, a.d + b.d}; }
  friend HandDual operator-(const HandDual& a, const HandDual& b) { return {a.v - b.v, a.d - b.d}; }
  friend HandDual operator*(const HandDual& a, const HandDual& b) { return {a.v * b.v, a.d * b.v + b.d * a.v}; }
  friend HandDual operator*(double a, const HandDual& b) { return {a * b.v, b.d * a}; }
  friend HandDual operator*(const HandDual& a, double b) { return {a.v * b, a.d * b}; }
  friend HandDual operator-(const HandDual& a) { return {-a.v, -a.d}; }
};

struct Setup {
  Setup() : problem(options()) {
    u = problem.initial_guess();
    u += Vector::Random(u.size()) * 1e-4;
    const auto& term = dynamic_cast<const KernelTerm<NewtonianFlowKernel<>>&>(*problem.assembler().terms()[0]);
    kernel = &term.kernel();
  }
  static ChannelOptions options() {
    ChannelOptions o;
    o.mesh = ChannelMeshSpec::preset("M2");
    o.fluid.Re = 1.0;  // with the convective term
    o.fluid.inertia = true;
    return o;
  }
  ChannelProblem problem;
  Vector u;
  const NewtonianFlowKernel<>* kernel = nullptr;
};

Setup& setup() {
  static Setup s;
  return s;
}

template <class Scalar, class Seed, class Extract>
void run(benchmark::State& state, Seed seed, Extract extract) {
  Setup& s = setup();
  constexpr int N = NewtonianFlowKernel<>::kSize;
  const double* params = s.problem.parameters().values();
  int dofs[N];
  std::array<Scalar, N> ud, rd;
  double J[N * N];
  for (auto _ : state) {
    for (int item = 0; item < s.kernel->num_items(); ++item) {
      s.kernel->item_dofs(item, dofs);
      for (int i = 0; i < N; ++i) ud[i] = seed(s.u[dofs[i]], i);
      s.kernel->evaluate<Scalar, double>(item, ud.data(), params, rd.data());
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) J[i * N + j] = extract(rd[i], j);
      benchmark::DoNotOptimize(J);
    }
  }
  state.counters["elements/s"] =
      benchmark::Counter(static_cast<double>(s.kernel->num_items()) * state.iterations(), benchmark::Counter::kIsRate);
}

void HandWrittenDual(benchmark::State& state) {
  constexpr int N = NewtonianFlowKernel<>::kSize;
  using D = HandDual<N>;
  run<D>(
      state,
      [](double v, int i) {
        D x(v);
        x.d[i] = 1.0;
        return x;
      },
      [](const D& d, int j) { return d.d[j]; });
}

void EigenAutoDiffScalar(benchmark::State& state) {
  using A = Dual<NewtonianFlowKernel<>::kSize>;
  run<A>(
      state, [](double v, int i) { return make_variable<NewtonianFlowKernel<>::kSize>(v, i); },
      [](const A& a, int j) { return a.derivatives()[j]; });
}

void ResidualOnly(benchmark::State& state) {
  Setup& s = setup();
  Vector F;
  for (auto _ : state) {
    s.problem.residual(s.u, F);
    benchmark::DoNotOptimize(F.data());
  }
}

}  // namespace

BENCHMARK(HandWrittenDual)->Unit(benchmark::kMillisecond);
BENCHMARK(EigenAutoDiffScalar)->Unit(benchmark::kMillisecond);
BENCHMARK(ResidualOnly)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
