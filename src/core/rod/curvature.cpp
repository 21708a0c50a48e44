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

}  // namespace

CurvatureDerivatives curvatureDerivatives(const Vec3& e, const Vec3& f, const EdgePairFrames& fr,
                                          bool hessian) {
  CurvatureDerivatives d;
  const double ne = e.norm(), nf = f.norm();
  const Vec3 te = e / ne, tf = f / nf;
  const double chi = 1.0 + te.dot(tf);
  const Vec3 tt = (te + tf) / chi;
  const Vec3 d1t = (fr.m1e + fr.m1f) / chi, d2t = (fr.m2e + fr.m2f) / chi;
  const Vec3 kb = 2.0 * te.cross(tf) / chi;
  const double k1 = 0.5 * kb.dot(fr.m2e + fr.m2f), k2 = -0.5 * kb.dot(fr.m1e + fr.m1f);
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
  if (!hessian) return d;

  const double ne2 = ne * ne, nf2 = nf * nf, nef = ne * nf;
  const Mat3 I = Mat3::Identity();
  const Mat3 tt_tt = tt * tt.transpose();
  {
    const Mat3 a = tf.cross(d2t) * tt.transpose();
    const Mat3 b = te.cross(d2t) * tt.transpose();
    const Mat3 kb_d2e = kb * fr.m2e.transpose(), kb_d2f = kb * fr.m2f.transpose();
    const Mat3 ee = (2.0 * k1 * tt_tt - a - a.transpose()) / ne2 -
                    k1 / (chi * ne2) * (I - te * te.transpose()) +
                    (kb_d2e + kb_d2e.transpose()) / (4.0 * ne2);
    const Mat3 ff = (2.0 * k1 * tt_tt + b + b.transpose()) / nf2 -
                    k1 / (chi * nf2) * (I - tf * tf.transpose()) +
                    (kb_d2f + kb_d2f.transpose()) / (4.0 * nf2);
    const Mat3 ef = -k1 / (chi * nef) * (I + te * tf.transpose()) +
                    (2.0 * k1 * tt_tt - a + b.transpose() - crossMatrix(d2t)) / nef;
    assemble(d.hessian[0], ee, ff, ef, -0.5 * kb.dot(fr.m2e), -0.5 * kb.dot(fr.m2f),
             (0.5 * kb.dot(fr.m1e) * tt - tf.cross(fr.m1e) / chi) / ne,
             (0.5 * kb.dot(fr.m1f) * tt - tf.cross(fr.m1f) / chi) / ne,
             (0.5 * kb.dot(fr.m1e) * tt + te.cross(fr.m1e) / chi) / nf,
             (0.5 * kb.dot(fr.m1f) * tt + te.cross(fr.m1f) / chi) / nf);
  }
  {
    const Mat3 a = tf.cross(d1t) * tt.transpose();
    const Mat3 b = te.cross(d1t) * tt.transpose();
    const Mat3 kb_d1e = kb * fr.m1e.transpose(), kb_d1f = kb * fr.m1f.transpose();
    const Mat3 ee = (2.0 * k2 * tt_tt + a + a.transpose()) / ne2 -
                    k2 / (chi * ne2) * (I - te * te.transpose()) -
                    (kb_d1e + kb_d1e.transpose()) / (4.0 * ne2);
    const Mat3 ff = (2.0 * k2 * tt_tt - b - b.transpose()) / nf2 -
                    k2 / (chi * nf2) * (I - tf * tf.transpose()) -
                    (kb_d1f + kb_d1f.transpose()) / (4.0 * nf2);
    const Mat3 ef = -k2 / (chi * nef) * (I + te * tf.transpose()) +
                    (2.0 * k2 * tt_tt + a - b.transpose() + crossMatrix(d1t)) / nef;
    assemble(d.hessian[1], ee, ff, ef, 0.5 * kb.dot(fr.m1e), 0.5 * kb.dot(fr.m1f),
             (0.5 * kb.dot(fr.m2e) * tt - tf.cross(fr.m2e) / chi) / ne,
             (0.5 * kb.dot(fr.m2f) * tt - tf.cross(fr.m2f) / chi) / ne,
             (0.5 * kb.dot(fr.m2e) * tt + te.cross(fr.m2e) / chi) / nf,
             (0.5 * kb.dot(fr.m2f) * tt + te.cross(fr.m2f) / chi) / nf);
  }
  return d;
}

TwistDerivatives twistDerivatives(const Vec3& e, const Vec3& f, const Vec3& kb, bool hessian) {
  TwistDerivatives d;
  const double ne = e.norm(), nf = f.norm();
  d.gradient.setZero();
  d.gradient.segment<3>(0) = 0.5 * kb / ne;
  d.gradient.segment<3>(4) = 0.5 * kb / nf;
  d.gradient(3) = -1.0;
  d.gradient(7) = 1.0;
  d.hessian.setZero();
  if (!hessian) return d;
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
