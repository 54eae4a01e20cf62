// SE(3) pose-graph optimisation (loop closure): vertices are camera poses T_w_c, edges
// relative measurements T_i_j (= T_w_i^-1 * T_w_j) with a 6x6 information matrix ordered
// [translation; rotation] like SE3::log. The edge error is E = T_i_j^-1 * T_w_i^-1 * T_w_j,
// e = [t(E); 2 vec(q(E))] (~ log(E) for small errors).
//
// Stateless; thread safety: optimize() is const and may run concurrently on different graphs.
#pragma once

#include <string>
#include <Eigen/Core>
#include <vector>

#include "core/se3.h"
#include "optim/measurement.h"

namespace plslam {

class OptionTable;

struct PoseGraphProblem {
  struct Vertex {
    SE3 T_w_c;           ///< initial pose, camera in world
    bool fixed = false;  ///< held constant (at least one should be; otherwise the first is)
  };
  struct Edge {
    int i = -1;                                                                 ///< index of the first vertex
    int j = -1;                                                                 ///< index of the second vertex
    SE3 T_i_j;                                                                  ///< measured pose of j in i
    Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();  ///< [trans; rot] order
  };
  std::vector<Vertex> vertices;
  std::vector<Edge> edges;

  /// Diagonal information from sigmas: translation sigma (metres) and rotation sigma (radians).
  static Eigen::Matrix<double, 6, 6> information(double sigma_trans_m, double sigma_rot_rad);
};

struct PoseGraphResult {
  std::vector<SE3> T_w_c;        ///< per vertex (the input when status != kOk)
  double initial_cost = 0.0;     ///< 0.5 * sum e^T info e (robustified when a loss is set) before
  double final_cost = 0.0;       ///< the same after
  int iterations = 0;            ///< solver iterations
  double time_ms = 0.0;          ///< wall time of optimize()
  OptimStatus status = OptimStatus::kNoObservations;
  bool ok() const { return status == OptimStatus::kOk; }
};

/// Configuration keys: each field's key, doc string and range are where it is bound, in
/// bindPoseGraphOptions (optim/option_keys.cpp). `plslam run --print-config` lists them.
struct PoseGraphOptions {
  int max_iterations = 100;
  double max_time_s = 0.0;
  double huber_delta = 0.0;
  int num_threads = 1;
};

/// Binds `prefix` + "iterations", "max_time_s", "huber_delta", "threads".
void bindPoseGraphOptions(OptionTable* table, const std::string& prefix, PoseGraphOptions* options);

class PoseGraphOptimizer {
 public:
  explicit PoseGraphOptimizer(PoseGraphOptions options = {});
  /// Throws DataError when an edge refers to a vertex out of range, links a vertex to
  /// itself, or has an information matrix that is not symmetric positive definite.
  PoseGraphResult optimize(const PoseGraphProblem& problem) const;
  const PoseGraphOptions& options() const { return options_; }

 private:
  PoseGraphOptions options_;
};

}  // namespace plslam
