#include "cloth_hair_sim/node/state_io.h"

#include <algorithm>
#include <vector>

#include <ros/names.h>
#include <ros/serialization.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/state_file.h"
#include "cloth_hair_sim/core/io/state_stream.h"

namespace chs_node {
namespace {

using Request = cloth_hair_sim::LoadGarment::Request;
using HairRequest = cloth_hair_sim::LoadHair::Request;

constexpr const char* kTag = "cloth_hair_sim simulation";

template <class Message>
std::string serialized(const Message& req) {
  const std::uint32_t n = ros::serialization::serializationLength(req);
  std::vector<std::uint8_t> bytes(n);
  ros::serialization::OStream s(bytes.data(), n);
  ros::serialization::serialize(s, req);
  return std::string(bytes.begin(), bytes.end());
}

template <class Message>
Message deserialized(const std::string& text, chs::StateReader& in, const char* what) {
  std::vector<std::uint8_t> bytes(text.begin(), text.end());
  ros::serialization::IStream s(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  Message req;
  try {
    ros::serialization::deserialize(s, req);
  } catch (const ros::serialization::StreamOverrunException&) {
    in.fail(std::string("a ") + what + " request is truncated");
  }
  if (s.getLength() != 0) in.fail(std::string("a ") + what + " request has trailing bytes");
  return req;
}

void writePose(chs::StateWriter& out, const Eigen::Isometry3d& pose) {
  out.matrix(pose.matrix());
}

Eigen::Isometry3d readPose(chs::StateReader& in, const char* what) {
  Eigen::Isometry3d pose;
  pose.matrix() = in.matrix(what);
  return pose;
}

void writeAttachmentMotion(chs::StateWriter& out, const FrameAttachment& a) {
  writePose(out, a.from);
  writePose(out, a.to);
  out.u64(a.stale);
}

void readAttachmentMotion(chs::StateReader& in, FrameAttachment& a) {
  a.from = readPose(in, "attachment start pose");
  a.to = readPose(in, "attachment end pose");
  a.stale = in.u64("attachment staleness") != 0;
}

void checkGraspName(chs::StateReader& in, const std::string& name, const std::string& who) {
  std::string error;
  if (name.empty() || name.find('/') != std::string::npos || !ros::names::validate(name, error))
    in.fail(who + "not a valid grasp name");
}

void writeGarment(chs::StateWriter& out, const Garment& g) {
  out.text(g.name);
  out.u64(static_cast<std::uint64_t>(g.colour));
  out.text(serialized(g.request));
  writePose(out, g.world_from_request_frame);
  out.u64(g.world_from_frames.size());
  for (const auto& [frame, pose] : g.world_from_frames) {
    out.text(frame);
    writePose(out, pose);
  }
  out.vectors(g.reference.mesh.vertices);
  out.u64(g.frame_pins.size());
  for (const auto& a : g.frame_pins) writeAttachmentMotion(out, a);
  g.dynamics->writeState(out);
}

Garment readGarment(chs::StateReader& in, const SimParams& params) {
  const std::string name = in.text("garment name");
  const std::uint64_t colour = in.u64("garment colour");
  const Request req = deserialized<Request>(in.text("LoadGarment request"), in, "LoadGarment");
  if (req.name != name) in.fail("garment '" + name + "': its request names '" + req.name + "'");
  const Eigen::Isometry3d world_from_request_frame = readPose(in, "garment pose");
  std::map<std::string, Eigen::Isometry3d> frames;
  const std::uint64_t n_frames = in.u64("attachment frame count");
  for (std::uint64_t k = 0; k < n_frames; ++k) {
    const std::string frame = in.text("attachment frame");
    frames[frame] = readPose(in, "attachment frame pose");
  }
  Garment g;
  try {
    g = buildGarment(req, world_from_request_frame, frames, params);
  } catch (const std::exception& e) {
    in.fail("garment '" + name + "' cannot be rebuilt: " + e.what());
  }
  const std::string who = "garment '" + name + "': ";
  const std::vector<Eigen::Vector3d> mesh =
      in.vectors("reference mesh", g.reference.mesh.vertices.size());
  if (mesh != g.reference.mesh.vertices)
    in.fail(who + "its mesh differs from the saved one" +
            (req.mesh_file.empty() ? std::string() : " (file '" + req.mesh_file + "' changed?)"));
  in.expectCount("frame pin groups", g.frame_pins.size());
  for (auto& a : g.frame_pins) readAttachmentMotion(in, a);
  try {
    g.dynamics->readState(in);
  } catch (const chs::InputError& e) {
    throw chs::InputError(std::string(e.what()) + " (" + who + "backend state)");
  }
  g.colour = static_cast<int>(colour);
  return g;
}

void writeGrasp(chs::StateWriter& out, const Grasp& g) {
  out.text(g.name);
  out.text(g.garment);
  const FrameAttachment& a = g.attachment;
  out.text(a.frame_id);
  out.ints(a.vertices);
  out.vectors(a.offsets);
  writePose(out, a.attached_at);
  writeAttachmentMotion(out, a);
  out.vectors(g.last_velocity);
  out.vectors({g.sum.force, g.sum.torque});
  out.u64(static_cast<std::uint64_t>(g.samples));
}

Grasp readGrasp(chs::StateReader& in, const std::map<std::string, Garment>& garments) {
  Grasp g{in.text("grasp name"),
          in.text("grasp garment"),
          FrameAttachment(in.text("grasp frame"), {}, {}, Eigen::Isometry3d::Identity()),
          {},
          {},
          {},
          0};
  const std::string who = "grasp '" + g.name + "': ";
  checkGraspName(in, g.name, who);
  const auto garment = garments.find(g.garment);
  if (garment == garments.end()) in.fail(who + "its garment '" + g.garment + "' is not saved");
  FrameAttachment& a = g.attachment;
  a.vertices = in.ints("grasped vertices");
  const int n = garment->second.dynamics->numVertices();
  for (int v : a.vertices)
    if (v < 0 || v >= n) in.fail(who + "vertex " + std::to_string(v) + " out of range");
  a.offsets = in.vectors("grasp offsets", a.vertices.size());
  a.attached_at = readPose(in, "grasp pose");
  readAttachmentMotion(in, a);
  g.last_velocity = in.vectors("grasp velocities");
  if (!g.last_velocity.empty() && g.last_velocity.size() != a.vertices.size())
    in.fail(who + std::to_string(g.last_velocity.size()) + " velocities for " +
            std::to_string(a.vertices.size()) + " vertices");
  const std::vector<Eigen::Vector3d> sum = in.vectors("grasp wrench sum", 2);
  g.sum.force = sum[0];
  g.sum.torque = sum[1];
  g.samples = static_cast<int>(in.u64("grasp wrench samples"));
  return g;
}

void writeHair(chs::StateWriter& out, const Hair& h) {
  out.text(h.name);
  out.text(serialized(h.request));
  writePose(out, h.attached_at);
  writePose(out, h.from);
  writePose(out, h.to);
  out.u64(h.stale);
  out.real(h.body->settings().grid_spacing);
  h.body->writeState(out);
}

Hair readHair(chs::StateReader& in, chs::rod::HairSettings settings, int display_default) {
  const std::string name = in.text("hair name");
  const HairRequest req = deserialized<HairRequest>(in.text("LoadHair request"), in, "LoadHair");
  if (req.name != name) in.fail("hair '" + name + "': its request names '" + req.name + "'");
  const Eigen::Isometry3d attached_at = readPose(in, "hair root frame");
  const Eigen::Isometry3d from = readPose(in, "hair root frame start");
  const Eigen::Isometry3d to = readPose(in, "hair root frame end");
  const bool stale = in.u64("hair staleness") != 0;
  settings.grid_spacing = in.real("hair grid spacing");
  Hair h;
  try {
    h = buildHair(req, attached_at, settings, display_default);
  } catch (const std::exception& e) {
    in.fail("hair '" + name + "' cannot be rebuilt: " + e.what());
  }
  try {
    h.body->readState(in);
  } catch (const chs::InputError& e) {
    throw chs::InputError(std::string(e.what()) + " (hair '" + name + "': its strands changed?)");
  }
  h.from = from;
  h.to = to;
  h.stale = stale;
  return h;
}

void writeHairGrasp(chs::StateWriter& out, const HairGrasp& g) {
  out.text(g.name);
  out.text(g.hair);
  out.text(g.frame_id);
  out.u64(static_cast<std::uint64_t>(g.grip));
  writePose(out, g.attached_at);
  writePose(out, g.from);
  writePose(out, g.to);
  out.u64(g.stale);
  out.vectors({g.sum.force, g.sum.torque});
  out.u64(static_cast<std::uint64_t>(g.samples));
}

HairGrasp readHairGrasp(chs::StateReader& in, const std::map<std::string, Hair>& hairs) {
  HairGrasp g;
  g.name = in.text("hair grasp name");
  g.hair = in.text("hair grasp hair");
  g.frame_id = in.text("hair grasp frame");
  g.grip = static_cast<int>(in.u64("hair grasp grip"));
  const std::string who = "grasp '" + g.name + "': ";
  checkGraspName(in, g.name, who);
  const auto hair = hairs.find(g.hair);
  if (hair == hairs.end()) in.fail(who + "its hair '" + g.hair + "' is not saved");
  try {
    hair->second.body->gripVertices(g.grip);
  } catch (const chs::InputError&) {
    in.fail(who + "its grip is not in hair '" + g.hair + "'");
  }
  g.attached_at = readPose(in, "hair grasp pose");
  g.from = readPose(in, "hair grasp start pose");
  g.to = readPose(in, "hair grasp end pose");
  g.stale = in.u64("hair grasp staleness") != 0;
  const std::vector<Eigen::Vector3d> sum = in.vectors("hair grasp wrench sum", 2);
  g.sum.force = sum[0];
  g.sum.torque = sum[1];
  g.samples = static_cast<int>(in.u64("hair grasp wrench samples"));
  return g;
}

}  // namespace

std::string encodeSimulation(const std::string& backend, const SimClock& clock,
                             const std::map<std::string, Garment>& garments,
                             const std::map<std::string, Grasp>& grasps,
                             const std::map<std::string, Hair>& hairs,
                             const std::map<std::string, HairGrasp>& hair_grasps) {
  chs::StateWriter out;
  out.text(kTag);
  // A request of another definition would deserialise into the wrong fields.
  out.text(ros::message_traits::md5sum<Request>());
  out.text(ros::message_traits::md5sum<HairRequest>());
  out.text(backend);
  out.real(clock.sim_time);
  out.u64(clock.steps);
  out.u64(clock.paused);
  out.u64(static_cast<std::uint64_t>(clock.rollbacks));
  out.u64(static_cast<std::uint64_t>(clock.unconverged_solves));
  out.u64(garments.size());
  for (const auto& [name, g] : garments) writeGarment(out, g);
  out.u64(grasps.size());
  for (const auto& [name, g] : grasps) writeGrasp(out, g);
  out.u64(hairs.size());
  for (const auto& [name, h] : hairs) writeHair(out, h);
  out.u64(hair_grasps.size());
  for (const auto& [name, g] : hair_grasps) writeHairGrasp(out, g);
  return out.data();
}

SavedSimulation readSimulation(const std::string& path, const SimParams& params,
                               const chs::rod::HairSettings& hair, int display_default) {
  chs::StateReader in(chs::readStateFile(path), path);
  in.expectText(kTag, "contents");
  const std::string md5 = in.text("LoadGarment definition");
  if (md5 != ros::message_traits::md5sum<Request>())
    in.fail("saved by a build whose LoadGarment service has another definition");
  if (in.text("LoadHair definition") != ros::message_traits::md5sum<HairRequest>())
    in.fail("saved by a build whose LoadHair service has another definition");
  const std::string backend = in.text("dynamics backend");
  if (backend != params.dynamics_backend)
    in.fail("saved with dynamics_backend '" + backend + "', this node runs '" +
            params.dynamics_backend + "'");
  SavedSimulation s;
  s.clock.sim_time = in.real("sim time");
  s.clock.steps = in.u64("step count");
  s.clock.paused = in.u64("paused flag") != 0;
  s.clock.rollbacks = static_cast<int>(in.u64("rollback count"));
  s.clock.unconverged_solves = static_cast<int>(in.u64("unconverged solve count"));
  const std::uint64_t n_garments = in.u64("garment count");
  // The garments share one world: the first one's grid spacing, unless ~mpm/grid_spacing sets one.
  SimParams shared = params;
  for (std::uint64_t k = 0; k < n_garments; ++k) {
    Garment g = readGarment(in, shared);
    if (shared.mpm.grid_spacing <= 0.0 && g.body)
      shared.mpm.grid_spacing = g.body->field().spacing();
    const std::string name = g.name;
    if (!s.garments.emplace(name, std::move(g)).second) in.fail("garment '" + name + "' twice");
  }
  const std::uint64_t n_grasps = in.u64("grasp count");
  for (std::uint64_t k = 0; k < n_grasps; ++k) {
    Grasp g = readGrasp(in, s.garments);
    const std::string name = g.name;
    if (!s.grasps.emplace(name, std::move(g)).second) in.fail("grasp '" + name + "' twice");
  }
  const std::uint64_t n_hairs = in.u64("hair count");
  for (std::uint64_t k = 0; k < n_hairs; ++k) {
    Hair h = readHair(in, hair, display_default);
    const std::string name = h.name;
    if (s.garments.count(name) || !s.hairs.emplace(name, std::move(h)).second)
      in.fail("hair '" + name + "' twice, or a garment of its name");
  }
  const std::uint64_t n_hair_grasps = in.u64("hair grasp count");
  for (std::uint64_t k = 0; k < n_hair_grasps; ++k) {
    HairGrasp g = readHairGrasp(in, s.hairs);
    const std::string name = g.name;
    if (s.grasps.count(name) || !s.hair_grasps.emplace(name, std::move(g)).second)
      in.fail("grasp '" + name + "' twice");
  }
  in.expectEnd();
  return s;
}

}  // namespace chs_node
