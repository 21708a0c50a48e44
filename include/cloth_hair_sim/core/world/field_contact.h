#pragma once
#include <functional>
#include <vector>

#include "cloth_hair_sim/core/mpm/particle_projection.h"
#include "cloth_hair_sim/core/mpm/sparse_grid.h"

namespace chs {

// Contact and Coulomb friction between the velocity fields of different bodies where they share
// grid nodes (multi-velocity-field MPM contact, after Bardenhagen et al. 2000). One velocity per
// node would drag two layers a cell apart together whatever their friction; with a field per body
// each keeps its own node velocities and the bodies interact only where they touch.
//
// At a node where fields b have mass m_b, momentum p_b and first moment of mass q_b = sum_p w_ip
// m_p x_p (so that x_b = q_b / m_b is where b's material near the node lies), field b meets the
// rest r of the fields there along the normal n: the bodies' surface normal at the node where
// they have one (a shell's, summed over the fields with their signs aligned), oriented from x_b
// towards x_r, else the direction x_r - x_b itself. d = (x_r - x_b) . n is their separation (the
// surface normal keeps a sheet's edge, where x_b moves inwards, from reading as a tilted wall).
// Contact is speculative: b may approach r at w = (v_b - v_r) . n no faster than (d - delta) /
// dt, so that the two come no closer than the contact distance delta within the step and no
// layer passes another between two grid updates; closer than 1.5 delta the contact is closed
// (no approach at all), so that a resting layer gets its impulse every step, and closer than
// delta the two separate at a fifth of (delta - d) / dt, so that a resting layer's gap does not
// drift shut by round-off and interpolation a little each step. The excess dw is
// removed by the normal impulse J_n = mu_r dw (mu_r = m_b m_r / (m_b + m_r)), and the tangential
// relative velocity v_t by a Coulomb impulse of at most friction J_n (stick when that stops it).
// All changes are computed from the velocities before the stage and then applied; between two
// fields they conserve linear momentum exactly (three or more at one node: each meets the
// mass-weighted rest, momentum to first order).
struct FieldContactSettings {
  double friction = 0.3;          // Coulomb mu between bodies
  double contact_distance = 0.0;  // delta [m]
};

struct FieldContactStats {
  int shared_nodes = 0;   // nodes where two or more fields have mass
  int contact_nodes = 0;  // of those, nodes where an impulse acted
};

// One body's field: its grid (all of the same spacing), the particles that gave it its mass with
// their supports (for q_b), and what fills a surface normal per node (any sign, any length; left
// empty when the body has none), called only for a field that may meet another.
struct ContactField {
  mpm::SparseGrid* grid = nullptr;
  std::vector<mpm::MassCarriers> carriers;
  std::function<void(std::vector<Eigen::Vector3d>&)> normals;
};

// degree: the B-spline degree of all fields. touched[b] is set when field b changed. Throws
// InputError for fields of different spacings or normals that do not match their grid.
FieldContactStats resolveFieldContact(std::vector<ContactField>& fields, int degree, double dt,
                                      const FieldContactSettings& settings,
                                      std::vector<char>* touched = nullptr);

}  // namespace chs
