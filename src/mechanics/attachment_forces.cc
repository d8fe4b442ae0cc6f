#include "mechanics/attachment_forces.h"

#include <algorithm>

namespace viscera::mechanics {

void AddCurvePointOuter(const CurvePoint& at, const Mat3& h, BlockBand* m) {
  for (int a = 0; a < 4; ++a) {
    for (int b = a; b < 4; ++b) {
      const double wab = at.w(a) * at.w(b);
      if (wab != 0.0) m->Add(at.first + a, at.first + b, wab * h);
    }
  }
}

double AddAttachmentForces(std::span<const Attachment> attachments, const Points& q,
                           const Points& qd, Points* F, BlockBand* K, BlockBand* D) {
  double energy = 0.0;
  for (const Attachment& att : attachments) {
    const Vec3 x = Model::Evaluate(att.at, q) - att.anchor;
    const Vec3 v = Model::Evaluate(att.at, qd);
    const double l = x.norm();
    Vec3 f = -att.damping * v;
    Mat3 h = Mat3::Zero();
    if (att.rest_length <= 0.0) {
      energy += 0.5 * att.stiffness * l * l;
      f -= att.stiffness * x;
      h = att.stiffness * Mat3::Identity();
    } else if (l > 0.0) {
      const Vec3 t = x / l;
      const double stretch = l - att.rest_length;
      energy += 0.5 * att.stiffness * stretch * stretch;
      f -= att.stiffness * stretch * t;
      const Mat3 ttT = t * t.transpose();
      h = att.stiffness *
          (ttT + std::max(0.0, 1.0 - att.rest_length / l) * (Mat3::Identity() - ttT));
    }
    for (int a = 0; a < 4; ++a) F->row(att.at.first + a) += att.at.w(a) * f.transpose();
    if (K) AddCurvePointOuter(att.at, h, K);
    if (D && att.damping > 0.0) AddCurvePointOuter(att.at, att.damping * Mat3::Identity(), D);
  }
  return energy;
}

}  // namespace viscera::mechanics
