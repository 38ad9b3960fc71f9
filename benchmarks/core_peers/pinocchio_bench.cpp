// Pinocchio's C++ side of benchmarks/run_core_peers.sh: per-call time of the tool pose, the tool
// Jacobian, RNEA and CRBA on a URDF, and the reference values the Rust side checks kinema and `k`
// against. Built by run_core_peers.sh against the headers and libraries of the `pin` wheel.
//
//   pinocchio_bench states URDF TIP JOINTS N SEED OUT.csv   seeded states and Pinocchio's results
//   pinocchio_bench time URDF TIP JOINTS STATES.csv MS      ns per call, one line per operation
//
// JOINTS: the moving joints kinema's chain to TIP has, comma-separated, or `all`; every other joint
// is locked at 0 (buildReducedModel), as kinema's URDF import holds joints off the chain.
//
// A state row of OUT.csv: q, qd, qdd (n each), then the results at it: the tool pose (R row-major,
// then p: 12), the tool Jacobian (6 x n row-major, rows [v; w], LOCAL_WORLD_ALIGNED: velocity of
// the tool point and angular velocity in world axes, kinema's base-frame convention), tau =
// rnea(q, qd, qdd) with gravity (0, 0, -9.81), M = crba(q) with the lower triangle filled (n x n).

#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace pin = pinocchio;

namespace {

struct Arm {
  pin::Model model;
  pin::FrameIndex tip;
};

std::vector<std::string> split(const std::string &s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, sep);) out.push_back(item);
  return out;
}

Arm load(const std::string &urdf, const std::string &tip, const std::string &joints) {
  pin::Model full;
  pin::urdf::buildModel(urdf, full);
  Arm arm;
  if (joints == "all") {
    arm.model = full;
  } else {
    std::vector<std::string> keep = split(joints, ',');
    std::vector<pin::JointIndex> lock;
    for (pin::JointIndex j = 1; j < (pin::JointIndex)full.njoints; ++j)
      if (std::find(keep.begin(), keep.end(), full.names[j]) == keep.end()) lock.push_back(j);
    arm.model = pin::buildReducedModel(full, lock, pin::neutral(full));
  }
  if (arm.model.nq != arm.model.nv) throw std::runtime_error("a joint with nq != nv");
  if (!arm.model.existFrame(tip)) throw std::runtime_error("no frame " + tip);
  arm.tip = arm.model.getFrameId(tip);
  return arm;
}

struct State {
  Eigen::VectorXd q, qd, qdd;
};

// Keeps a computed value alive without the compiler seeing it read: an empty asm that claims to use
// the memory.
template <typename T> void keep(const T &value) { asm volatile("" : : "g"(&value) : "memory"); }

std::vector<State> read_states(const std::string &path, int n) {
  std::vector<State> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f = split(line, ',');
    State s{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
    for (int i = 0; i < n; ++i) {
      s.q[i] = std::stod(f[i]);
      s.qd[i] = std::stod(f[n + i]);
      s.qdd[i] = std::stod(f[2 * n + i]);
    }
    out.push_back(s);
  }
  return out;
}

int states(const Arm &arm, int count, unsigned seed, const std::string &out_path) {
  const pin::Model &model = arm.model;
  pin::Data data(model);
  const int n = model.nv;
  std::mt19937_64 rng(seed);
  auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  std::FILE *out = std::fopen(out_path.c_str(), "w");
  if (!out) throw std::runtime_error("cannot write " + out_path);
  for (int k = 0; k < count; ++k) {
    State s{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
    for (int i = 0; i < n; ++i) {
      // Within the limits and within [-pi, pi] (continuous joints have none).
      double lo = std::max(model.lowerPositionLimit[i], -M_PI), hi = std::min(model.upperPositionLimit[i], M_PI);
      s.q[i] = uniform(lo, hi);
      s.qd[i] = uniform(-2, 2);
      s.qdd[i] = uniform(-3, 3);
    }
    std::vector<double> row;
    for (const Eigen::VectorXd *v : {&s.q, &s.qd, &s.qdd})
      for (int i = 0; i < n; ++i) row.push_back((*v)[i]);
    pin::forwardKinematics(model, data, s.q);
    const pin::SE3 &pose = pin::updateFramePlacement(model, data, arm.tip);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) row.push_back(pose.rotation()(r, c));
    for (int r = 0; r < 3; ++r) row.push_back(pose.translation()[r]);
    pin::Data::Matrix6x jac = pin::Data::Matrix6x::Zero(6, n);
    pin::computeFrameJacobian(model, data, s.q, arm.tip, pin::LOCAL_WORLD_ALIGNED, jac);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < n; ++c) row.push_back(jac(r, c));
    const Eigen::VectorXd &tau = pin::rnea(model, data, s.q, s.qd, s.qdd);
    for (int i = 0; i < n; ++i) row.push_back(tau[i]);
    pin::crba(model, data, s.q);
    data.M.triangularView<Eigen::StrictlyLower>() = data.M.transpose().triangularView<Eigen::StrictlyLower>();
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) row.push_back(data.M(r, c));
    for (size_t i = 0; i < row.size(); ++i) std::fprintf(out, i ? ",%.17g" : "%.17g", row[i]);
    std::fprintf(out, "\n");
  }
  std::fclose(out);
  return 0;
}

// ns per call of `call(state)`, cycling through the states: the median over batches of 256 calls
// (each batch's mean) within about `ms` milliseconds, after a short warm-up.
template <typename F> double time_op(const std::vector<State> &states, double ms, F call) {
  using clock = std::chrono::steady_clock;
  const size_t batch = 256;
  size_t k = 0;
  for (size_t i = 0; i < 20 * batch; ++i) call(states[k++ % states.size()]);
  std::vector<double> per_call;
  const auto end = clock::now() + std::chrono::microseconds((long)(ms * 1000));
  while (clock::now() < end || per_call.size() < 11) {
    const auto t0 = clock::now();
    for (size_t i = 0; i < batch; ++i) call(states[k++ % states.size()]);
    const auto t1 = clock::now();
    per_call.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / batch);
  }
  std::nth_element(per_call.begin(), per_call.begin() + per_call.size() / 2, per_call.end());
  return per_call[per_call.size() / 2];
}

int time_all(const Arm &arm, const std::string &states_path, double ms) {
  const pin::Model &model = arm.model;
  pin::Data data(model);
  const int n = model.nv;
  const std::vector<State> st = read_states(states_path, n);
  pin::Data::Matrix6x jac = pin::Data::Matrix6x::Zero(6, n);
  auto report = [](const char *op, double ns) { std::printf("%s %.2f\n", op, ns); };
  report("fk", time_op(st, ms, [&](const State &s) {
           pin::forwardKinematics(model, data, s.q);
           keep(pin::updateFramePlacement(model, data, arm.tip));
         }));
  report("jacobian", time_op(st, ms, [&](const State &s) {
           pin::computeFrameJacobian(model, data, s.q, arm.tip, pin::LOCAL_WORLD_ALIGNED, jac);
           keep(jac);
         }));
  report("rnea", time_op(st, ms, [&](const State &s) { keep(pin::rnea(model, data, s.q, s.qd, s.qdd)); }));
  report("crba", time_op(st, ms, [&](const State &s) { keep(pin::crba(model, data, s.q)); }));
  report("crba-world", time_op(st, ms, [&](const State &s) { keep(pin::crba(model, data, s.q, pin::Convention::WORLD)); }));
  report("crba-full", time_op(st, ms, [&](const State &s) {
           pin::crba(model, data, s.q);
           data.M.triangularView<Eigen::StrictlyLower>() = data.M.transpose().triangularView<Eigen::StrictlyLower>();
           keep(data.M);
         }));
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "states" && argc == 8) {
      return states(load(argv[2], argv[3], argv[4]), std::atoi(argv[5]), (unsigned)std::atol(argv[6]), argv[7]);
    }
    if (mode == "time" && argc == 7) {
      return time_all(load(argv[2], argv[3], argv[4]), argv[5], std::atof(argv[6]));
    }
    std::cerr << "usage: pinocchio_bench states URDF TIP JOINTS N SEED OUT.csv\n"
                 "       pinocchio_bench time URDF TIP JOINTS STATES.csv MS\n";
    return 2;
  } catch (const std::exception &e) {
    std::cerr << "pinocchio_bench: " << e.what() << "\n";
    return 1;
  }
}
