// robot_model.cpp — URDF (urdfdom, with tinyxml2 for line numbers and the <armature> extension) and the
// robot TOML (default pose, standing gains) into a RobotModel.
#include "robot/robot_model.h"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <toml++/toml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "robot/kinematics.h"

namespace robot {

const std::array<const char*, kNumJoints> kJointNames = {
    "left_hip_pitch_joint",     "left_hip_roll_joint",       "left_hip_yaw_joint",         "left_knee_joint",
    "left_ankle_pitch_joint",   "left_ankle_roll_joint",     "right_hip_pitch_joint",      "right_hip_roll_joint",
    "right_hip_yaw_joint",      "right_knee_joint",          "right_ankle_pitch_joint",    "right_ankle_roll_joint",
    "waist_yaw_joint",          "left_shoulder_pitch_joint", "left_shoulder_roll_joint",   "left_shoulder_yaw_joint",
    "left_elbow_joint",         "left_wrist_roll_joint",     "right_shoulder_pitch_joint", "right_shoulder_roll_joint",
    "right_shoulder_yaw_joint", "right_elbow_joint",         "right_wrist_roll_joint",
};

namespace {

using engine::Error;
using engine::located;

// collects urdfdom's console_bridge messages while it parses, so they can go into our error
class CaptureOutput : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN && messages.empty()) messages = text;
  }
  std::string messages;
};

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() =
      Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  return t;
}

// line numbers of <link name=...> and <joint name=...> elements, and the <armature> values
struct XmlIndex {
  std::map<std::string, int> linkLine, jointLine;
  std::map<std::string, double> armature;
};

// the line of a link or joint urdfdom found; one it names that the index lacks is an error in the file, never a crash
int lineOf(const std::map<std::string, int>& lines, const std::string& name, const std::string& file,
           const char* what) {
  const auto it = lines.find(name);
  if (it == lines.end())
    throw Error(located(file, 0, std::string("<") + what + "> '" + name + "' is not found again by its name"));
  return it->second;
}

XmlIndex indexXml(const std::string& text, const std::string& file) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw Error(located(file, doc.ErrorLineNum(), std::string("malformed XML: ") + doc.ErrorName()));
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw Error(located(file, 1, "no <robot> element"));
  XmlIndex index;
  // names are printable ASCII: urdfdom reads the file with another XML parser, which keeps a carriage return or
  // writes a Latin-1 character reference as one byte where tinyxml2 does not, so such a name would not be found again
  auto checkName = [&](const char* n, const tinyxml2::XMLElement* e, const char* what) {
    for (const char* c = n; *c; ++c)
      if (static_cast<unsigned char>(*c) < 0x20 || static_cast<unsigned char>(*c) >= 0x7f)
        throw Error(located(
            file, e->GetLineNum(),
            std::string("<") + what + "> name holds a control or non-ASCII character: names are " + "printable ASCII"));
  };
  for (auto* e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link"))
    if (const char* n = e->Attribute("name")) {
      checkName(n, e, "link");
      index.linkLine[n] = e->GetLineNum();
    }
  for (auto* e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) {
    const char* n = e->Attribute("name");
    if (!n) throw Error(located(file, e->GetLineNum(), "<joint> without a name"));
    checkName(n, e, "joint");
    index.jointLine[n] = e->GetLineNum();
    if (auto* a = e->FirstChildElement("armature")) {
      double v = 0;
      if (a->QueryDoubleAttribute("value", &v) != tinyxml2::XML_SUCCESS || !std::isfinite(v) || v < 0 || v > 10)
        throw Error(located(file, a->GetLineNum(), "<armature value> must be a number in [0, 10] kg m^2"));
      index.armature[n] = v;
    }
  }
  return index;
}

engine::LinkDef convertLink(const urdf::Link& link, const std::string& file, int line) {
  engine::LinkDef def;
  def.name = link.name;
  if (!link.inertial) throw Error(located(file, line, "link '" + link.name + "' has no <inertial>"));
  const urdf::Inertial& in = *link.inertial;
  // a humanoid's link: anything far outside these bounds makes the solver diverge rather than simulate a robot
  if (!(in.mass > 0) || !std::isfinite(in.mass) || in.mass > 1000)
    throw Error(located(file, line, "link '" + link.name + "' must have a mass in (0, 1000] kg"));
  def.mass = in.mass;
  const Eigen::Isometry3d inPose = toIsometry(in.origin);
  def.com = inPose.translation();
  if (!def.com.allFinite() || def.com.norm() > 10)
    throw Error(located(file, line, "link '" + link.name + "': the inertial origin must lie within 10 m of the link"));
  Eigen::Matrix3d i;
  i << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  def.inertia = inPose.linear() * i * inPose.linear().transpose();
  if (!def.inertia.allFinite() || def.inertia.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff() <= 0)
    throw Error(located(file, line, "link '" + link.name + "' inertia is not positive definite"));
  if (def.inertia.selfadjointView<Eigen::Lower>().eigenvalues().maxCoeff() > 100)
    throw Error(located(file, line, "link '" + link.name + "' inertia is above 100 kg m^2"));
  for (const auto& c : link.collision_array) {
    if (!c || !c->geometry) continue;
    engine::ColliderDef col;
    col.name = c->name;
    col.pose = toIsometry(c->origin);
    switch (c->geometry->type) {
      case urdf::Geometry::SPHERE:
        col.kind = engine::ShapeKind::Sphere;
        col.radius = static_cast<const urdf::Sphere&>(*c->geometry).radius;
        break;
      case urdf::Geometry::BOX: {
        const auto& b = static_cast<const urdf::Box&>(*c->geometry);
        col.kind = engine::ShapeKind::Box;
        col.halfExtents = 0.5 * Eigen::Vector3d(b.dim.x, b.dim.y, b.dim.z);
        break;
      }
      case urdf::Geometry::CYLINDER: {  // simulated as a capsule (see the URDF's header comment)
        const auto& cy = static_cast<const urdf::Cylinder&>(*c->geometry);
        col.kind = engine::ShapeKind::Capsule;
        col.radius = cy.radius;
        col.halfLength = 0.5 * cy.length;
        break;
      }
      default:
        throw Error(
            located(file, line, "link '" + link.name + "': only sphere, box and cylinder collisions are supported"));
    }
    if (!(col.radius >= 0) || !(col.halfExtents.minCoeff() >= 0) || !(col.halfLength >= 0))
      throw Error(located(file, line, "link '" + link.name + "': negative collision size"));
    def.colliders.push_back(col);
  }
  return def;
}

double tomlNumber(const toml::node_view<const toml::node>& v, const std::string& file, int line,
                  const std::string& what) {
  if (auto d = v.value<double>(); d && std::isfinite(*d)) return *d;
  throw Error(located(file, line, what + " must be a finite number"));
}

}  // namespace

void parseG1Urdf(const std::string& text, const std::string& file, RobotModel* model) {
  const XmlIndex index = indexXml(text, file);

  CaptureOutput capture;
  console_bridge::useOutputHandler(&capture);
  urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(text);
  console_bridge::restorePreviousOutputHandler();
  if (!urdf)
    throw Error(
        located(file, 0, "invalid URDF: " + (capture.messages.empty() ? "rejected by urdfdom" : capture.messages)));

  const urdf::LinkConstSharedPtr root = urdf->getRoot();
  if (!root || root->name != "pelvis") throw Error(located(file, 0, "the root link must be 'pelvis'"));
  for (const auto& [name, joint] : urdf->joints_)
    if (joint->type != urdf::Joint::REVOLUTE)
      throw Error(located(file, index.jointLine.count(name) ? index.jointLine.at(name) : 0,
                          "joint '" + name + "' is not revolute (only revolute joints are supported)"));
  if (urdf->joints_.size() != kNumJoints)
    throw Error(located(
        file, 0, "expected " + std::to_string(kNumJoints) + " joints, found " + std::to_string(urdf->joints_.size())));

  model->articulation.base = convertLink(*root, file, lineOf(index.linkLine, root->name, file, "link"));
  model->articulation.links.clear();
  model->joints.assign(kNumJoints, JointInfo{});
  std::map<std::string, int> linkIndex{{root->name, -1}};
  for (int j = 0; j < kNumJoints; ++j) {
    const std::string name = kJointNames[static_cast<size_t>(j)];
    const urdf::JointConstSharedPtr joint = urdf->getJoint(name);
    if (!joint) throw Error(located(file, 0, "missing joint '" + name + "' (the G1 needs all 23 joints by name)"));
    const int line = lineOf(index.jointLine, name, file, "joint");
    if (!linkIndex.count(joint->parent_link_name))
      throw Error(located(file, line,
                          "joint '" + name + "': parent link '" + joint->parent_link_name +
                              "' must be driven by an earlier joint in the G1 order"));
    const urdf::LinkConstSharedPtr child = urdf->getLink(joint->child_link_name);
    engine::LinkDef def = convertLink(*child, file, lineOf(index.linkLine, child->name, file, "link"));
    def.parent = linkIndex.at(joint->parent_link_name);
    def.joint = name;
    def.jointFrame = toIsometry(joint->parent_to_joint_origin_transform);
    def.axis = Eigen::Vector3d(joint->axis.x, joint->axis.y, joint->axis.z);
    if (def.axis.norm() < 0.5) throw Error(located(file, line, "joint '" + name + "' has a zero axis"));
    def.axis.normalize();
    if (!joint->limits || !(joint->limits->lower < joint->limits->upper) || !(joint->limits->effort > 0))
      throw Error(located(file, line, "joint '" + name + "' needs <limit> with lower < upper and effort > 0"));
    def.lower = joint->limits->lower;
    def.upper = joint->limits->upper;

    JointInfo& info = model->joints[static_cast<size_t>(j)];
    info.name = name;
    info.lower = def.lower;
    info.upper = def.upper;
    info.effort = joint->limits->effort;
    info.velocity = joint->limits->velocity;
    info.armature = index.armature.count(name) ? index.armature.at(name) : 0.0;
    // rotor inertia: reflected inertia about the joint axis, added to the link (see feasibility.md §1)
    def.inertia += info.armature * def.axis * def.axis.transpose();

    linkIndex[child->name] = j;
    model->articulation.links.push_back(std::move(def));
  }
  model->leftFoot = linkIndex.count("left_ankle_roll_link") ? linkIndex.at("left_ankle_roll_link") : -1;
  model->rightFoot = linkIndex.count("right_ankle_roll_link") ? linkIndex.at("right_ankle_roll_link") : -1;
  model->torso = linkIndex.count("torso_link") ? linkIndex.at("torso_link") : -1;
  if (model->leftFoot < 0 || model->rightFoot < 0 || model->torso < 0)
    throw Error(located(file, 0, "links left_ankle_roll_link, right_ankle_roll_link and torso_link are required"));
  model->totalMass = model->articulation.base.mass;
  for (const auto& l : model->articulation.links) model->totalMass += l.mass;
}

RobotModel loadRobotModel(const std::string& configPath) {
  RobotModel model;
  model.configPath = configPath;
  const std::string configText = engine::readFile(configPath);
  toml::table cfg;
  try {
    cfg = toml::parse(configText, configPath);
  } catch (const toml::parse_error& e) {
    throw Error(located(configPath, static_cast<int>(e.source().begin.line), std::string(e.description())));
  }
  const auto urdfName = cfg["urdf"].value<std::string>();
  if (!urdfName) throw Error(located(configPath, 0, "missing 'urdf = \"file.urdf\"'"));
  model.urdfPath = (std::filesystem::path(configPath).parent_path() / *urdfName).string();
  const std::string urdfText = engine::readFile(model.urdfPath);
  parseG1Urdf(urdfText, model.urdfPath, &model);

  const toml::table* joints = cfg["joints"].as_table();
  if (!joints) throw Error(located(configPath, 0, "missing [joints] table"));
  for (auto&& [key, node] : *joints) {
    const int line = static_cast<int>(node.source().begin.line);
    const std::string name(key.str());
    auto it = std::find(kJointNames.begin(), kJointNames.end(), name);
    if (it == kJointNames.end()) throw Error(located(configPath, line, "unknown joint '" + name + "'"));
    const toml::table* t = node.as_table();
    if (!t) throw Error(located(configPath, line, "joint '" + name + "' must be a table {default, kp, kd}"));
    for (auto&& [k, v] : *t)
      if (k != "default" && k != "kp" && k != "kd")
        throw Error(located(configPath, line, "joint '" + name + "': unknown key '" + std::string(k.str()) + "'"));
    JointInfo& info = model.joints[static_cast<size_t>(it - kJointNames.begin())];
    const toml::node_view<const toml::node> view(node);
    info.defaultPosition = tomlNumber(view["default"], configPath, line, name + ".default");
    info.standKp = tomlNumber(view["kp"], configPath, line, name + ".kp");
    info.standKd = tomlNumber(view["kd"], configPath, line, name + ".kd");
    if (info.defaultPosition < info.lower || info.defaultPosition > info.upper)
      throw Error(located(configPath, line, name + ".default is outside the joint limits"));
    if (info.standKp < 0 || info.standKd < 0) throw Error(located(configPath, line, name + ": gains must be >= 0"));
  }
  for (int j = 0; j < kNumJoints; ++j)
    if (!joints->contains(kJointNames[static_cast<size_t>(j)]))
      throw Error(
          located(configPath, 0, std::string("[joints] is missing '") + kJointNames[static_cast<size_t>(j)] + "'"));

  std::vector<double> q(kNumJoints);
  for (int j = 0; j < kNumJoints; ++j) q[static_cast<size_t>(j)] = model.joints[static_cast<size_t>(j)].defaultPosition;
  model.spawnHeight = -lowestColliderPoint(model.articulation, q);

  engine::Hasher h;
  h.bytes(urdfText.data(), urdfText.size());
  h.bytes(configText.data(), configText.size());
  model.hash = h.value();
  return model;
}

std::string defaultRobotConfigPath() { return engine::projectFile("assets/robots/g1_23dof.toml"); }

}  // namespace robot
