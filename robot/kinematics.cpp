// kinematics.cpp — forward kinematics and collider extents for an ArticulationDef.
#include "robot/kinematics.h"

#include <algorithm>
#include <limits>

namespace robot {

std::vector<Eigen::Isometry3d> forwardKinematics(const engine::ArticulationDef& def, const std::vector<double>& q) {
  std::vector<Eigen::Isometry3d> poses(def.links.size() + 1, Eigen::Isometry3d::Identity());
  for (size_t i = 0; i < def.links.size(); ++i) {
    const engine::LinkDef& l = def.links[i];
    const Eigen::Isometry3d rot(Eigen::AngleAxisd(q.at(i), l.axis));
    poses[i + 1] = poses[static_cast<size_t>(l.parent + 1)] * l.jointFrame * rot;
  }
  return poses;
}

double lowestColliderPoint(const engine::ArticulationDef& def, const std::vector<double>& q) {
  const std::vector<Eigen::Isometry3d> poses = forwardKinematics(def, q);
  double lowest = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k <= def.links.size(); ++k) {
    const engine::LinkDef& l = k == 0 ? def.base : def.links[k - 1];
    for (const engine::ColliderDef& c : l.colliders) {
      const Eigen::Isometry3d w = poses[k] * c.pose;
      switch (c.kind) {
        case engine::ShapeKind::Sphere:
          lowest = std::min(lowest, w.translation().z() - c.radius);
          break;
        case engine::ShapeKind::Capsule: {
          const Eigen::Vector3d a = w * Eigen::Vector3d(0, 0, c.halfLength),
                                b = w * Eigen::Vector3d(0, 0, -c.halfLength);
          lowest = std::min(lowest, std::min(a.z(), b.z()) - c.radius);
          break;
        }
        case engine::ShapeKind::Box:
          for (int s = 0; s < 8; ++s) {
            const Eigen::Vector3d corner((s & 1 ? 1 : -1) * c.halfExtents.x(), (s & 2 ? 1 : -1) * c.halfExtents.y(),
                                         (s & 4 ? 1 : -1) * c.halfExtents.z());
            lowest = std::min(lowest, (w * corner).z());
          }
          break;
        case engine::ShapeKind::Plane:
          break;
      }
    }
  }
  return lowest;
}

}  // namespace robot
