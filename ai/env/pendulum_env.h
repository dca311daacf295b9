// pendulum_env.h — N pendulum swing-up environments (gym Pendulum-v1 dynamics) as a VecEnv: a small,
// fast, deterministic task for testing PPO and the trainer. Observation [cos th, sin th, thdot]; action
// clipped to [-1, 1] and scaled to a torque of +-2; episodes are truncated after 200 steps, never terminated.
#pragma once

#include <random>
#include <vector>

#include "ai/env/vec_env.h"

namespace ai {

class PendulumEnv final : public VecEnv {
 public:
  /// Maximum torque (N m) for an action of +-1.
  static constexpr double kMaxTorque = 2.0;
  /// Time step (s).
  static constexpr double kDt = 0.05;
  /// Angular velocity limit (rad/s).
  static constexpr double kMaxSpeed = 8.0;
  /// Gravity (m/s^2), mass (kg), length (m).
  static constexpr double kGravity = 10.0, kMass = 1.0, kLength = 1.0;
  /// Steps before an episode is truncated.
  static constexpr int kEpisodeSteps = 200;

  /// numEnvs pendulums; call reset before step.
  explicit PendulumEnv(int numEnvs);

  int numEnvs() const override { return int(theta_.size()); }
  int observationSize() const override { return 3; }
  int actionSize() const override { return 1; }
  /// "angle" (-th^2), "velocity" (-0.1 thdot^2), "torque" (-0.001 u^2): they sum to the reward.
  std::vector<std::string> rewardTermNames() const override { return {"angle", "velocity", "torque"}; }
  /// Random starts th in [-pi, pi), thdot in [-1, 1) from seed.
  void reset(uint64_t seed, Eigen::MatrixXf* observations) override;
  /// Reward -(th^2 + 0.1 thdot^2 + 0.001 u^2) with th wrapped to [-pi, pi), from the state before the step.
  void step(const Eigen::MatrixXf& actions, StepResult* result) override;

 private:
  void startEpisode(int n);
  void observe(int n, Eigen::MatrixXf* out, int column) const;

  std::mt19937_64 rng_;
  std::vector<double> theta_, thetaDot_, episodeReturn_;
  std::vector<int> steps_;
};

}  // namespace ai
