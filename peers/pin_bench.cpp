// Times Pinocchio's crba, rnea, aba and computeCoriolisMatrix on a model written by
// pin_model.write_flat or write_model (joint list with merged inertias + a fixed state;
// joint types RX RY RZ RU PX PY PZ PU and FF, the free flyer, whose q has nv + 1 entries).
// Usage: pin_bench MODEL.txt [aba|crba|rnea]  -> prints results (key value lines) on
// stdout; with an algorithm's name, times only that one (what the report times beside
// ours).
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace pinocchio;

static std::vector<double> read_vec(std::istream &in, int n) {
  std::vector<double> v(n);
  for (auto &x : v) in >> x;
  return v;
}

struct Timing { double median, min, max; };

// ns per call: median, min and max of 21 batches of ~20 ms each, after a warm-up.
template <class F> static Timing time_ns(F &&f) {
  using clk = std::chrono::steady_clock;
  for (int i = 0; i < 20000; ++i) f();  // warm-up
  // calibrate a batch to ~20 ms
  long n = 1000;
  for (;;) {
    auto t0 = clk::now();
    for (long i = 0; i < n; ++i) f();
    double s = std::chrono::duration<double>(clk::now() - t0).count();
    if (s > 0.02) break;
    n *= 2;
  }
  std::vector<double> per;
  for (int r = 0; r < 21; ++r) {
    auto t0 = clk::now();
    for (long i = 0; i < n; ++i) f();
    per.push_back(std::chrono::duration<double, std::nano>(clk::now() - t0).count() / n);
  }
  std::sort(per.begin(), per.end());
  return {per[per.size() / 2], per.front(), per.back()};
}

int main(int argc, char **argv) {
  if (argc < 2) { std::cerr << "usage: pin_bench MODEL.txt\n"; return 2; }
  std::ifstream in(argv[1]);
  if (!in) { std::cerr << "cannot open " << argv[1] << "\n"; return 2; }
  int nj; in >> nj;
  Model model;
  auto g = read_vec(in, 3);
  model.gravity.linear() = Eigen::Vector3d(g[0], g[1], g[2]);
  for (int k = 0; k < nj; ++k) {
    std::string t; int parent; in >> t >> parent;
    auto r = read_vec(in, 9), p = read_vec(in, 3), a = read_vec(in, 3), mi = read_vec(in, 4), I = read_vec(in, 9);
    Eigen::Matrix3d R; R << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
    SE3 place(R, Eigen::Vector3d(p[0], p[1], p[2]));
    Eigen::Vector3d axis(a[0], a[1], a[2]);
    Eigen::Matrix3d Ic; Ic << I[0], I[1], I[2], I[3], I[4], I[5], I[6], I[7], I[8];
    Inertia inertia(mi[0], Eigen::Vector3d(mi[1], mi[2], mi[3]), Symmetric3(Ic));
    JointIndex id;
    std::string name = "j" + std::to_string(k);
    if (t == "RX") id = model.addJoint(parent, JointModelRX(), place, name);
    else if (t == "RY") id = model.addJoint(parent, JointModelRY(), place, name);
    else if (t == "RZ") id = model.addJoint(parent, JointModelRZ(), place, name);
    else if (t == "RU") id = model.addJoint(parent, JointModelRevoluteUnaligned(axis), place, name);
    else if (t == "PX") id = model.addJoint(parent, JointModelPX(), place, name);
    else if (t == "PY") id = model.addJoint(parent, JointModelPY(), place, name);
    else if (t == "PZ") id = model.addJoint(parent, JointModelPZ(), place, name);
    else if (t == "PU") id = model.addJoint(parent, JointModelPrismaticUnaligned(axis), place, name);
    else if (t == "FF") id = model.addJoint(parent, JointModelFreeFlyer(), place, name);
    else { std::cerr << "unknown joint type " << t << "\n"; return 2; }
    model.appendBodyToJoint(id, inertia, SE3::Identity());
  }
  const int n = model.nv;
  auto qv = read_vec(in, model.nq), vv = read_vec(in, n), tv = read_vec(in, n);
  if (!in) { std::cerr << "model file truncated\n"; return 2; }
  Eigen::VectorXd q = Eigen::Map<Eigen::VectorXd>(qv.data(), model.nq), v = Eigen::Map<Eigen::VectorXd>(vv.data(), n),
                  tau = Eigen::Map<Eigen::VectorXd>(tv.data(), n);
  Data data(model);

  // results at the state, for the cross-check against the Python bindings
  crba(model, data, q);
  data.M.triangularView<Eigen::StrictlyLower>() = data.M.transpose().triangularView<Eigen::StrictlyLower>();
  std::printf("M");
  for (int i = 0; i < n * n; ++i) std::printf(" %.17g", data.M(i / n, i % n));
  std::printf("\n");
  Eigen::VectorXd a = Eigen::VectorXd::Constant(n, 0.3);
  rnea(model, data, q, v, a);
  std::printf("rnea");
  for (int i = 0; i < n; ++i) std::printf(" %.17g", data.tau[i]);
  std::printf("\n");
  aba(model, data, q, v, tau);
  std::printf("aba");
  for (int i = 0; i < n; ++i) std::printf(" %.17g", data.ddq[i]);
  std::printf("\n");

  double sink = 0;
  auto show = [](const char *key, Timing t) {
    std::printf("%s %.3f\n%s_range %.3f %.3f\n", key, t.median, key, t.min, t.max);
  };
  // One algorithm only (`aba`, `crba` or `rnea`): what the report times beside ours.
  const std::string only = argc > 2 ? argv[2] : "";
  const bool all = only.empty();
  if (all || only == "crba")
    show("crba_ns", time_ns([&] { crba(model, data, q); sink += data.M(0, 0); }));
  if (all || only == "rnea")
    show("rnea_ns", time_ns([&] { rnea(model, data, q, v, a); sink += data.tau[0]; }));
  if (all || only == "aba")
    show("aba_ns", time_ns([&] { aba(model, data, q, v, tau); sink += data.ddq[0]; }));
  if (all) {
    show("coriolis_ns", time_ns([&] { computeCoriolisMatrix(model, data, q, v); sink += data.C(0, 0); }));
  }
  std::fprintf(stderr, "(sink %g)\n", sink);
  return 0;
}
