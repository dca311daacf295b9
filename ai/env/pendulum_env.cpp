// pendulum_env.cpp — gym Pendulum-v1 dynamics in double, vectorised over N environments with auto-reset.
#include "ai/env/pendulum_env.h"

#include <algorithm>
#include <cmath>

#include "ai/ppo/gaussian.h"

namespace ai {
namespace {

double wrapAngle(double th) { return std::fmod(std::fmod(th + M_PI, 2.0 * M_PI) + 2.0 * M_PI, 2.0 * M_PI) - M_PI; }

}  // namespace

PendulumEnv::PendulumEnv(int numEnvs)
    : theta_(size_t(numEnvs), 0.0),
      thetaDot_(size_t(numEnvs), 0.0),
      episodeReturn_(size_t(numEnvs), 0.0),
      steps_(size_t(numEnvs), 0) {}

void PendulumEnv::startEpisode(int n) {
  theta_[size_t(n)] = (2.0 * uniformClosedOpen(&rng_) - 1.0) * M_PI;
  thetaDot_[size_t(n)] = 2.0 * uniformClosedOpen(&rng_) - 1.0;
  episodeReturn_[size_t(n)] = 0.0;
  steps_[size_t(n)] = 0;
}

void PendulumEnv::observe(int n, Eigen::MatrixXf* out, int column) const {
  (*out)(0, column) = float(std::cos(theta_[size_t(n)]));
  (*out)(1, column) = float(std::sin(theta_[size_t(n)]));
  (*out)(2, column) = float(thetaDot_[size_t(n)]);
}

void PendulumEnv::reset(uint64_t seed, Eigen::MatrixXf* observations) {
  rng_.seed(seed);
  observations->resize(3, numEnvs());
  for (int n = 0; n < numEnvs(); ++n) {
    startEpisode(n);
    observe(n, observations, n);
  }
}

void PendulumEnv::step(const Eigen::MatrixXf& actions, StepResult* result) {
  const int envs = numEnvs();
  result->observations.resize(3, envs);
  result->finalObservations.resize(3, envs);
  result->rewards.resize(envs);
  result->terminated.assign(size_t(envs), 0);
  result->truncated.assign(size_t(envs), 0);
  result->episodeReturns.clear();
  result->episodeLengths.clear();
  result->rewardTermSums.assign(3, 0.0);

  for (int n = 0; n < envs; ++n) {
    const size_t i = size_t(n);
    const double u = kMaxTorque * std::clamp(double(actions(0, n)), -1.0, 1.0);
    const double th = theta_[i], thDot = thetaDot_[i];

    // cost from the state before the step (as gym)
    const double angleCost = wrapAngle(th) * wrapAngle(th), velocityCost = 0.1 * thDot * thDot,
                 torqueCost = 0.001 * u * u;
    const double reward = -(angleCost + velocityCost + torqueCost);
    result->rewards(n) = float(reward);
    result->rewardTermSums[0] -= angleCost;
    result->rewardTermSums[1] -= velocityCost;
    result->rewardTermSums[2] -= torqueCost;

    // semi-implicit Euler with the speed limit
    const double newThDot = std::clamp(
        thDot + (3.0 * kGravity / (2.0 * kLength) * std::sin(th) + 3.0 / (kMass * kLength * kLength) * u) * kDt,
        -kMaxSpeed, kMaxSpeed);
    theta_[i] = th + newThDot * kDt;
    thetaDot_[i] = newThDot;
    episodeReturn_[i] += reward;
    ++steps_[i];

    // time limit: report the episode, keep its last observation, start a new one
    if (steps_[i] >= kEpisodeSteps) {
      result->truncated[i] = 1;
      observe(n, &result->finalObservations, n);
      result->episodeReturns.push_back(float(episodeReturn_[i]));
      result->episodeLengths.push_back(steps_[i]);
      startEpisode(n);
    }
    observe(n, &result->observations, n);
  }
}

}  // namespace ai
