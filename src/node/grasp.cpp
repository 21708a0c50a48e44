#include "cloth_hair_sim/node/grasp.h"

namespace chs_node {

FrameAttachment::FrameAttachment(std::string frame, std::vector<int> held,
                                 const std::vector<Eigen::Vector3d>& x,
                                 const Eigen::Isometry3d& world_from_frame)
    : frame_id(std::move(frame)),
      vertices(std::move(held)),
      attached_at(world_from_frame),
      from(world_from_frame),
      to(world_from_frame) {
  const Eigen::Isometry3d frame_from_world = world_from_frame.inverse();
  for (int v : vertices) offsets.push_back(frame_from_world * x.at(v));
}

void FrameAttachment::pinAt(chs::ClothDynamics& dynamics, double alpha) const {
  const Eigen::Isometry3d pose = alpha >= 1.0 ? to : interpolate(from, to, alpha);
  for (std::size_t k = 0; k < vertices.size(); ++k) dynamics.pin(vertices[k], pose * offsets[k]);
}

void FrameAttachment::unpin(chs::ClothDynamics& dynamics) const {
  for (int v : vertices) dynamics.unpin(v);
}

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double t) {
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = qa.slerp(t, qb).toRotationMatrix();
  out.translation() = (1.0 - t) * a.translation() + t * b.translation();
  return out;
}

chs::SurfaceVelocity rigidVelocity(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                                   double duration) {
  chs::SurfaceVelocity u;
  u.origin = a.translation();
  if (!(duration > 0.0)) return u;
  u.linear = (b.translation() - a.translation()) / duration;
  const Eigen::AngleAxisd turn(b.linear() * a.linear().transpose());
  u.angular = turn.angle() * turn.axis() / duration;
  return u;
}

std::vector<int> freeVerticesNear(const chs::ClothDynamics& dynamics, const Eigen::Vector3d& centre,
                                  double radius) {
  std::vector<int> out;
  for (int v = 0; v < dynamics.numVertices(); ++v)
    if (!dynamics.isPinned(v) && (dynamics.positions()[v] - centre).norm() <= radius)
      out.push_back(v);
  return out;
}

}  // namespace chs_node
