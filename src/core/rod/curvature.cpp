#include "cloth_hair_sim/core/rod/curvature.h"

#include <Eigen/Geometry>

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

Mat3 crossMatrix(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

// Fills the symmetric 8 x 8 from its edge blocks (ee, ff, ef) and angle terms.
void assemble(Matrix8d& h, const Mat3& ee, const Mat3& ff, const Mat3& ef, double tete, double tftf,
              const Vec3& e_te, const Vec3& e_tf, const Vec3& f_te, const Vec3& f_tf) {
  h.setZero();
  h.block<3, 3>(0, 0) = ee;
  h.block<3, 3>(4, 4) = ff;
  h.block<3, 3>(0, 4) = ef;
  h.block<3, 3>(4, 0) = ef.transpose();
  h(3, 3) = tete;
  h(7, 7) = tftf;
  h.block<3, 1>(0, 3) = e_te;
  h.block<1, 3>(3, 0) = e_te.transpose();
  h.block<3, 1>(0, 7) = e_tf;
  h.block<1, 3>(7, 0) = e_tf.transpose();
  h.block<3, 1>(4, 3) = f_te;
  h.block<1, 3>(3, 4) = f_te.transpose();
  h.block<3, 1>(4, 7) = f_tf;
  h.block<1, 3>(7, 4) = f_tf.transpose();
}

// The quantities both the gradients and the Hessian are built from.
struct Basics {
  double ne, nf, chi, k1, k2;
  Vec3 te, tf, tt, d1t, d2t, kb;
};

Basics basics(const Vec3& e, const Vec3& f, const EdgePairFrames& fr) {
  Basics b;
  b.ne = e.norm();
  b.nf = f.norm();
  b.te = e / b.ne;
  b.tf = f / b.nf;
  b.chi = 1.0 + b.te.dot(b.tf);
  b.tt = (b.te + b.tf) / b.chi;
  b.d1t = (fr.m1e + fr.m1f) / b.chi;
  b.d2t = (fr.m2e + fr.m2f) / b.chi;
  b.kb = 2.0 * b.te.cross(b.tf) / b.chi;
  b.k1 = 0.5 * b.kb.dot(fr.m2e + fr.m2f);
  b.k2 = -0.5 * b.kb.dot(fr.m1e + fr.m1f);
  return b;
}

}  // namespace

CurvatureDerivatives curvatureDerivatives(const Vec3& e, const Vec3& f, const EdgePairFrames& fr) {
  const Basics q = basics(e, f, fr);
  const double ne = q.ne, nf = q.nf, k1 = q.k1, k2 = q.k2;
  const Vec3 &te = q.te, &tf = q.tf, &tt = q.tt, &d1t = q.d1t, &d2t = q.d2t, &kb = q.kb;
  CurvatureDerivatives d;
  d.kb = kb;
  d.kappa = {k1, k2};
  Vector8d& g1 = d.gradient[0];
  Vector8d& g2 = d.gradient[1];
  g1.segment<3>(0) = (-k1 * tt + tf.cross(d2t)) / ne;
  g1.segment<3>(4) = (-k1 * tt - te.cross(d2t)) / nf;
  g1(3) = -0.5 * kb.dot(fr.m1e);
  g1(7) = -0.5 * kb.dot(fr.m1f);
  g2.segment<3>(0) = (-k2 * tt - tf.cross(d1t)) / ne;
  g2.segment<3>(4) = (-k2 * tt + te.cross(d1t)) / nf;
  g2(3) = -0.5 * kb.dot(fr.m2e);
  g2(7) = -0.5 * kb.dot(fr.m2f);
  return d;
}

Matrix8d curvatureHessian(const Vec3& e, const Vec3& f, const EdgePairFrames& fr,
                          const Eigen::Vector2d& weights) {
  const Basics q = basics(e, f, fr);
  const double ne = q.ne, nf = q.nf, chi = q.chi, k1 = q.k1, k2 = q.k2;
  const Vec3 &te = q.te, &tf = q.tf, &tt = q.tt, &d1t = q.d1t, &d2t = q.d2t, &kb = q.kb;
  // Sum_c w_c hess kappa_c: every term of a curvature's Hessian is linear in its frame vectors
  // (kappa_1's in m2, kappa_2's in -m1 for the bending terms and in m1, m2 for the terms of the
  // angles), so the weighted sum is one Hessian of the weighted vectors, at the cost of one.
  const double w1 = weights[0], w2 = weights[1];
  const double K = w1 * k1 + w2 * k2;
  const Vec3 dt = w1 * d2t - w2 * d1t;
  const Vec3 De = w1 * fr.m2e - w2 * fr.m1e, Df = w1 * fr.m2f - w2 * fr.m1f;
  const Vec3 Ee = w1 * fr.m1e + w2 * fr.m2e, Ef = w1 * fr.m1f + w2 * fr.m2f;
  const double ne2 = ne * ne, nf2 = nf * nf, nef = ne * nf;
  const Mat3 I = Mat3::Identity();
  const Mat3 tt_tt = tt * tt.transpose();
  const Mat3 a = tf.cross(dt) * tt.transpose();
  const Mat3 b = te.cross(dt) * tt.transpose();
  const Mat3 kb_de = kb * De.transpose(), kb_df = kb * Df.transpose();
  const Mat3 ee = (2.0 * K * tt_tt - a - a.transpose()) / ne2 -
                  K / (chi * ne2) * (I - te * te.transpose()) +
                  (kb_de + kb_de.transpose()) / (4.0 * ne2);
  const Mat3 ff = (2.0 * K * tt_tt + b + b.transpose()) / nf2 -
                  K / (chi * nf2) * (I - tf * tf.transpose()) +
                  (kb_df + kb_df.transpose()) / (4.0 * nf2);
  const Mat3 ef = -K / (chi * nef) * (I + te * tf.transpose()) +
                  (2.0 * K * tt_tt - a + b.transpose() - crossMatrix(dt)) / nef;
  Matrix8d h;
  assemble(h, ee, ff, ef, -0.5 * kb.dot(De), -0.5 * kb.dot(Df),
           (0.5 * kb.dot(Ee) * tt - tf.cross(Ee) / chi) / ne,
           (0.5 * kb.dot(Ef) * tt - tf.cross(Ef) / chi) / ne,
           (0.5 * kb.dot(Ee) * tt + te.cross(Ee) / chi) / nf,
           (0.5 * kb.dot(Ef) * tt + te.cross(Ef) / chi) / nf);
  return h;
}

TwistDerivatives twistDerivatives(const Vec3& e, const Vec3& f, const Vec3& kb, bool hessian) {
  TwistDerivatives d;
  const double ne = e.norm(), nf = f.norm();
  d.gradient.setZero();
  d.gradient.segment<3>(0) = 0.5 * kb / ne;
  d.gradient.segment<3>(4) = 0.5 * kb / nf;
  d.gradient(3) = -1.0;
  d.gradient(7) = 1.0;
  if (!hessian) return d;
  d.hessian.setZero();
  const Vec3 te = e / ne, tf = f / nf;
  const double chi = 1.0 + te.dot(tf);
  const Vec3 tt = (te + tf) / chi;
  const Mat3 ee = -0.25 / (ne * ne) * (kb * (te + tt).transpose() + (te + tt) * kb.transpose());
  const Mat3 ff = -0.25 / (nf * nf) * (kb * (tf + tt).transpose() + (tf + tt) * kb.transpose());
  const Mat3 ef = 0.5 / (ne * nf) * (2.0 / chi * crossMatrix(te) - kb * tt.transpose());
  d.hessian.block<3, 3>(0, 0) = ee;
  d.hessian.block<3, 3>(4, 4) = ff;
  d.hessian.block<3, 3>(0, 4) = ef;
  d.hessian.block<3, 3>(4, 0) = ef.transpose();
  return d;
}

}  // namespace chs::rod
