// gae.cpp — GAE with fall / time-out / horizon handling.
#include "ai/ppo/gae.h"

#include <stdexcept>

namespace ai {

void computeGae(const Eigen::MatrixXf& rewards, const Eigen::MatrixXf& values, const FlagMatrix& terminated,
                const FlagMatrix& truncated, const Eigen::MatrixXf& truncatedValues, const Eigen::VectorXf& lastValues,
                double gamma, double lambda, Eigen::MatrixXf* advantages, Eigen::MatrixXf* returns) {
  const Eigen::Index steps = rewards.rows(), envs = rewards.cols();
  if (values.rows() != steps || values.cols() != envs || terminated.rows() != steps || terminated.cols() != envs ||
      truncated.rows() != steps || truncated.cols() != envs || truncatedValues.rows() != steps ||
      truncatedValues.cols() != envs || lastValues.size() != envs)
    throw std::invalid_argument("computeGae: inconsistent shapes");
  advantages->resize(steps, envs);
  returns->resize(steps, envs);

  for (Eigen::Index n = 0; n < envs; ++n) {
    double nextAdvantage = 0.0;  // A_{t+1} along the current (uncut) chain
    for (Eigen::Index t = steps - 1; t >= 0; --t) {
      double nextValue, carry;
      if (terminated(t, n)) {
        nextValue = 0.0;  // a fall: nothing after it
        carry = 0.0;
      } else if (truncated(t, n)) {
        nextValue = double(truncatedValues(t, n));  // time-out: the episode could have continued
        carry = 0.0;
      } else if (t == steps - 1) {
        nextValue = double(lastValues(n));  // horizon cut: continue from the next observation's value
        carry = 0.0;
      } else {
        nextValue = double(values(t + 1, n));
        carry = gamma * lambda * nextAdvantage;
      }
      const double delta = double(rewards(t, n)) + gamma * nextValue - double(values(t, n));
      nextAdvantage = delta + carry;
      (*advantages)(t, n) = float(nextAdvantage);
      (*returns)(t, n) = float(nextAdvantage + double(values(t, n)));
    }
  }
}

}  // namespace ai
