// Pinocchio 4.1 C++ timing of rnea, crba, aba and one RK4 step, the same quantities and the
// same JSON keys as `articula bench --json` (src/dynamics/bench.rs), for the side-by-side
// comparison of tools/bench_side_by_side.sh.
//
//   pinocchio_bench MODEL.txt CHECK.txt [BATCHES]
//
// MODEL.txt is the model as a Boost text archive written by export_model.py (Pinocchio's own
// URDF parser, run from Python); CHECK.txt one state and Pinocchio-Python's rnea there, which
// this program reproduces before timing (it stops if they differ by more than 1e-9 relative).
//
// What is timed (as articula's bench does): 16 random states (q: revolute angles uniform in
// [-pi, pi), prismatic [-0.5, 0.5), free flyer position in a 1 m box and a uniform random unit
// quaternion; v, a uniform in [-1, 1); tau = 0 for aba), cycled through in batches of at least
// 2 ms; the median over BATCHES (default 7) batches of the time per call. RK4 step: the
// classical RK4 on the configuration manifold, four aba calls and pinocchio::integrate for the
// stage and final configurations, dt = 1 ms, tau = 0.
//
// All Pinocchio algorithms are compiled here from its headers (header-only: this file does not
// define PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION, so nothing timed comes from the prebuilt
// library); see build.sh for the flags.
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/serialization.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using pinocchio::Data;
using pinocchio::Model;
using Vec = Eigen::VectorXd;

static const int STATES = 16;

// median over `batches` of the time per call of f (which returns how many calls it made), each
// batch repeating f for at least 2 ms
template <class F> double median_ns(int batches, F f) {
  std::vector<double> per_call;
  for (int b = 0; b < std::max(batches, 1); ++b) {
    auto start = std::chrono::steady_clock::now();
    long calls = 0;
    double el = 0.0;
    while (calls == 0 || el < 2e-3) {
      calls += f();
      el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    per_call.push_back(el * 1e9 / double(calls));
  }
  std::sort(per_call.begin(), per_call.end());
  return per_call[per_call.size() / 2];
}

static Vec read_row(std::ifstream &in, long n) {
  Vec x(n);
  for (long k = 0; k < n; ++k) in >> x[k];
  return x;
}

int main(int argc, char **argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MODEL.txt CHECK.txt [BATCHES]\n", argv[0]);
    return 2;
  }
  int batches = argc > 3 ? std::atoi(argv[3]) : 7;
  Model model;
  model.loadFromText(argv[1]);
  Data data(model);

  // the check row: the same model as Pinocchio-Python's
  std::ifstream in(argv[2]);
  long nq = 0, nv = 0;
  in >> nq >> nv;
  if (nq != model.nq || nv != model.nv) {
    std::fprintf(stderr, "check file is for nq %ld nv %ld, model has %d %d\n", nq, nv,
                 model.nq, model.nv);
    return 1;
  }
  Vec cq = read_row(in, nq), cv = read_row(in, nv), ca = read_row(in, nv),
      ctau = read_row(in, nv);
  pinocchio::rnea(model, data, cq, cv, ca);
  double err = (data.tau - ctau).norm() / std::max(1.0, ctau.norm());
  if (!(err < 1e-9)) {
    std::fprintf(stderr, "rnea differs from Pinocchio-Python's: relative %.3g\n", err);
    return 1;
  }

  // random states (see the file comment)
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> pi(-M_PI, M_PI), half(-0.5, 0.5), one(-1.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Vec> qs, vs, as;
  for (int s = 0; s < STATES; ++s) {
    Vec q = pinocchio::neutral(model);
    for (size_t j = 1; j < model.joints.size(); ++j) {
      const auto &jm = model.joints[j];
      int iq = jm.idx_q();
      std::string kind = jm.shortname();
      if (jm.nq() == 1) {
        q[iq] = kind.find("JointModelP") == 0 ? half(rng) : pi(rng);
      } else if (kind == "JointModelFreeFlyer" || kind == "JointModelSpherical") {
        int o = kind == "JointModelFreeFlyer" ? 3 : 0;
        for (int k = 0; k < o; ++k) q[iq + k] = half(rng);
        Eigen::Vector4d x(normal(rng), normal(rng), normal(rng), normal(rng));
        q.segment<4>(iq + o) = x.normalized();
      } else if (jm.nq() > 0) {
        std::fprintf(stderr, "joint %s: no random state rule\n", kind.c_str());
        return 1;
      }
    }
    Vec v(model.nv), a(model.nv);
    for (int k = 0; k < model.nv; ++k) v[k] = one(rng);
    for (int k = 0; k < model.nv; ++k) a[k] = one(rng);
    qs.push_back(q);
    vs.push_back(v);
    as.push_back(a);
  }
  const Vec tau0 = Vec::Zero(model.nv);
  volatile double sink = 0.0;

  double rnea_ns = median_ns(batches, [&] {
    for (int s = 0; s < STATES; ++s) sink = pinocchio::rnea(model, data, qs[s], vs[s], as[s])[0];
    return STATES;
  });
  // crba and aba in both of Pinocchio's conventions (LOCAL, its default, and WORLD); the
  // faster one is reported as crba_ns / aba_ns and used in the RK4 step
  auto time_crba = [&](pinocchio::Convention c) {
    return median_ns(batches, [&] {
      for (int s = 0; s < STATES; ++s) {
        pinocchio::crba(model, data, qs[s], c);
        sink = data.M(0, 0);
      }
      return STATES;
    });
  };
  auto time_aba = [&](pinocchio::Convention c) {
    return median_ns(batches, [&] {
      for (int s = 0; s < STATES; ++s)
        sink = pinocchio::aba(model, data, qs[s], vs[s], tau0, c)[0];
      return STATES;
    });
  };
  double crba_local = time_crba(pinocchio::Convention::LOCAL);
  double crba_world = time_crba(pinocchio::Convention::WORLD);
  double aba_local = time_aba(pinocchio::Convention::LOCAL);
  double aba_world = time_aba(pinocchio::Convention::WORLD);
  double crba_ns = std::min(crba_local, crba_world), aba_ns = std::min(aba_local, aba_world);
  const pinocchio::Convention conv =
      aba_world < aba_local ? pinocchio::Convention::WORLD : pinocchio::Convention::LOCAL;

  // RK4: k_i = (v_i, a_i), q_i = q (+) h c_i v_{i-1}, v_i = v + h c_i a_{i-1}
  const double h = 1e-3;
  Vec q1(model.nq), q2(model.nq), q3(model.nq), qn(model.nq), dq(model.nv);
  Vec v2(model.nv), v3(model.nv), v4(model.nv), vn(model.nv);
  Vec a1(model.nv), a2(model.nv), a3(model.nv), a4(model.nv);
  double rk4_ns = median_ns(batches, [&] {
    for (int s = 0; s < STATES; ++s) {
      const Vec &q = qs[s], &v = vs[s];
      a1 = pinocchio::aba(model, data, q, v, tau0, conv);
      v2 = v + 0.5 * h * a1;
      pinocchio::integrate(model, q, 0.5 * h * v, q1);
      a2 = pinocchio::aba(model, data, q1, v2, tau0, conv);
      v3 = v + 0.5 * h * a2;
      pinocchio::integrate(model, q, 0.5 * h * v2, q2);
      a3 = pinocchio::aba(model, data, q2, v3, tau0, conv);
      v4 = v + h * a3;
      pinocchio::integrate(model, q, h * v3, q3);
      a4 = pinocchio::aba(model, data, q3, v4, tau0, conv);
      dq = (h / 6.0) * (v + 2.0 * v2 + 2.0 * v3 + v4);
      vn = v + (h / 6.0) * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
      pinocchio::integrate(model, q, dq, qn);
      sink = qn[0] + vn[0];
    }
    return STATES;
  });
  (void)sink;
  std::printf("{\n  \"nv\": %d,\n  \"rnea_ns\": %.1f,\n  \"crba_ns\": %.1f,\n  \"aba_ns\": %.1f,\n"
              "  \"rk4_step_ns\": %.1f,\n  \"crba_local_ns\": %.1f,\n  \"crba_world_ns\": %.1f,\n"
              "  \"aba_local_ns\": %.1f,\n  \"aba_world_ns\": %.1f,\n  \"rnea_check_rel_err\": %.3g\n}\n",
              model.nv, rnea_ns, crba_ns, aba_ns, rk4_ns, crba_local, crba_world, aba_local,
              aba_world, err);
  return 0;
}
