// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/primitive.h"

#include <algorithm>
#include <cmath>

namespace underwater_stereo {
namespace sim {

Primitive::Primitive(ShapeType shape, const Eigen::Vector3f& centre, const Eigen::Matrix3f& rotation,
                     const Eigen::Vector3f& size_m)
    : shape_(shape), centre_(centre), rotation_(rotation), half_(size_m / 2.0F) {
  bound_radius_sq_ = half_.squaredNorm() * 1.0001F + 1e-8F;
  if (shape_ == ShapeType::kSphere) bound_radius_sq_ = half_.x() * half_.x();
}

bool Primitive::contains(const Eigen::Vector3f& point) const {
  const Eigen::Vector3f o = rotation_.transpose() * (point - centre_);
  switch (shape_) {
    case ShapeType::kSphere: return o.squaredNorm() < half_.x() * half_.x();
    case ShapeType::kCylinder: return o.head<2>().squaredNorm() < half_.x() * half_.x() && std::abs(o.z()) < half_.z();
    case ShapeType::kBox: return (o.cwiseAbs().array() < half_.array()).all();
    case ShapeType::kPanel: return false;
  }
  return false;
}

bool Primitive::intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_max, Hit& hit) const {
  // Cheap rejection against the bounding sphere before the exact test in the object frame.
  const Eigen::Vector3f oc = origin - centre_;
  const float b = oc.dot(dir);
  const float c = oc.squaredNorm() - bound_radius_sq_;
  if (c > 0.0F && b > 0.0F) return false;
  if (b * b - c < 0.0F) return false;

  const Eigen::Vector3f o = rotation_.transpose() * oc;
  const Eigen::Vector3f d = rotation_.transpose() * dir;
  float t = 0.0F;
  Eigen::Vector3f n_local;
  bool found = false;
  switch (shape_) {
    case ShapeType::kSphere: found = intersectSphere(o, d, t_max, t, n_local); break;
    case ShapeType::kCylinder: found = intersectCylinder(o, d, t_max, t, n_local); break;
    case ShapeType::kBox: found = intersectBox(o, d, t_max, t, n_local); break;
    case ShapeType::kPanel: found = intersectPanel(o, d, t_max, t, n_local); break;
  }
  if (!found) return false;
  hit.t = t;
  hit.local = o + t * d;
  hit.normal = rotation_ * n_local;
  return true;
}

bool Primitive::intersectSphere(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                                Eigen::Vector3f& n) const {
  const float r = half_.x();
  const float b = o.dot(d);
  const float disc = b * b - (o.squaredNorm() - r * r);
  if (disc < 0.0F) return false;
  const float s = std::sqrt(disc);
  t = -b - s;
  if (t <= 0.0F) t = -b + s;
  if (t <= 0.0F || t >= t_max) return false;
  n = (o + t * d) / r;
  return true;
}

bool Primitive::intersectCylinder(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                                  Eigen::Vector3f& n) const {
  const float r = half_.x();
  const float h = half_.z();
  bool found = false;
  t = t_max;
  // Curved side: x^2 + y^2 = r^2, |z| <= h.
  const float a = d.x() * d.x() + d.y() * d.y();
  if (a > 1e-12F) {
    const float b = o.x() * d.x() + o.y() * d.y();
    const float c = o.x() * o.x() + o.y() * o.y() - r * r;
    const float disc = b * b - a * c;
    if (disc >= 0.0F) {
      const float s = std::sqrt(disc);
      for (float root : {(-b - s) / a, (-b + s) / a}) {
        if (root > 0.0F && root < t) {
          const float z = o.z() + root * d.z();
          if (std::abs(z) <= h) {
            t = root;
            const Eigen::Vector3f p = o + root * d;
            n = Eigen::Vector3f(p.x() / r, p.y() / r, 0.0F);
            found = true;
            break;
          }
        }
      }
    }
  }
  // Caps: z = +-h, x^2 + y^2 <= r^2.
  if (std::abs(d.z()) > 1e-12F) {
    for (float zc : {-h, h}) {
      const float root = (zc - o.z()) / d.z();
      if (root > 0.0F && root < t) {
        const Eigen::Vector3f p = o + root * d;
        if (p.x() * p.x() + p.y() * p.y() <= r * r) {
          t = root;
          n = Eigen::Vector3f(0.0F, 0.0F, zc > 0.0F ? 1.0F : -1.0F);
          found = true;
        }
      }
    }
  }
  return found;
}

bool Primitive::intersectBox(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                             Eigen::Vector3f& n) const {
  float t_near = -1e30F, t_far = 1e30F;
  int axis_near = 0, axis_far = 0;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-12F) {
      if (std::abs(o[i]) > half_[i]) return false;
      continue;
    }
    float t1 = (-half_[i] - o[i]) / d[i];
    float t2 = (half_[i] - o[i]) / d[i];
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_near) {
      t_near = t1;
      axis_near = i;
    }
    if (t2 < t_far) {
      t_far = t2;
      axis_far = i;
    }
    if (t_near > t_far) return false;
  }
  int axis = axis_near;
  t = t_near;
  if (t <= 0.0F) {
    t = t_far;
    axis = axis_far;
  }
  if (t <= 0.0F || t >= t_max) return false;
  n = Eigen::Vector3f::Zero();
  n[axis] = (o[axis] + t * d[axis]) > 0.0F ? 1.0F : -1.0F;
  return true;
}

bool Primitive::intersectPanel(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                               Eigen::Vector3f& n) const {
  if (std::abs(d.z()) < 1e-12F) return false;
  t = -o.z() / d.z();
  if (t <= 0.0F || t >= t_max) return false;
  const Eigen::Vector3f p = o + t * d;
  if (std::abs(p.x()) > half_.x() || std::abs(p.y()) > half_.y()) return false;
  n = Eigen::Vector3f(0.0F, 0.0F, d.z() < 0.0F ? 1.0F : -1.0F);  // two-sided: face the viewer
  return true;
}

}  // namespace sim
}  // namespace underwater_stereo
