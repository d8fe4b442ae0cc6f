// The contacts' lane kernels (mechanics/contact_window.h) against the scalar code they replaced,
// bit for bit, onto K, D and F already holding random numbers (so that each entry's order of
// additions counts).
#include "mechanics/contact_window.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace viscera::mechanics {
namespace {

bool SameBits(const double* a, const double* b, size_t count) {
  return std::memcmp(a, b, count * sizeof(double)) == 0;
}

bool SameBits(const BlockBand& a, const BlockBand& b) {
  for (int i = 0; i < a.n(); ++i) {
    for (int d = 0; d < BlockBand::kWidth; ++d) {
      if (!SameBits(a.block(i, d).data(), b.block(i, d).data(), 9)) return false;
    }
  }
  return true;
}

class ContactWindowLanes : public ::testing::Test {
 protected:
  // Magnitudes spread over many binades, signs mixed: roundings differ for any other order.
  double Random() { return std::ldexp(u_(rng_), e_(rng_)); }
  Mat3 RandomMat() {
    Mat3 m;
    for (int e = 0; e < 9; ++e) m.data()[e] = Random();
    return m;
  }
  Sym3 RandomSym() { return {Random(), Random(), Random(), Random(), Random(), Random()}; }
  std::array<double, 4> RandomWeights() { return {Random(), Random(), Random(), Random()}; }
  BlockBand RandomBand(int n) {
    BlockBand band(n);
    for (int i = 0; i < n; ++i) {
      for (int d = 0; d < BlockBand::kWidth; ++d) band.block(i, d) = RandomMat();
    }
    return band;
  }

  std::mt19937 rng_{20261124};
  std::uniform_real_distribution<double> u_{-1.0, 1.0};
  std::uniform_int_distribution<int> e_{-8, 8};
};

TEST_F(ContactWindowLanes, AddOuterGivesAddSymmetricsBitsOnKAndD) {
  constexpr int kN = 12;
  for (int trial = 0; trial < 2000; ++trial) {
    const BlockBand k0 = RandomBand(kN), d0 = RandomBand(kN);
    const int first = trial % (kN - 3);
    const std::array<double, 4> w = RandomWeights();
    const Sym3 hk = RandomSym(), hd = RandomSym();
    const bool with_d = trial % 3 != 0;
    // The scalar code (the window's outer product before the lanes).
    BlockBand k_ref = k0, d_ref = d0;
    for (int a = 0; a < 4; ++a) {
      for (int b = a; b < 4; ++b) {
        const double wab = w[a] * w[b];
        k_ref.AddSymmetric(first + a, first + b, wab, hk);
        if (with_d) d_ref.AddSymmetric(first + a, first + b, wab, hd);
      }
    }
    BlockBand k = k0, d = d0;
    contact_window::AddOuter(first, w, hk, with_d ? &hd : nullptr, &k, &d);
    ASSERT_TRUE(SameBits(k, k_ref)) << "trial " << trial;
    ASSERT_TRUE(SameBits(d, d_ref)) << "trial " << trial;
  }
}

TEST_F(ContactWindowLanes, AddForceGivesTheRowSumsBits) {
  constexpr int kN = 10;
  for (int trial = 0; trial < 2000; ++trial) {
    Points f0(kN, 3);
    for (int e = 0; e < f0.size(); ++e) f0.data()[e] = Random();
    const int first = trial % (kN - 3);
    const std::array<double, 4> w = RandomWeights();
    const Vec3 f(Random(), Random(), Random());
    Points ref = f0;
    for (int a = 0; a < 4; ++a) ref.row(first + a) += w[a] * f.transpose();
    Points got = f0;
    contact_window::AddForce(got.data(), first, w, f);
    ASSERT_TRUE(SameBits(got.data(), ref.data(), ref.size())) << "trial " << trial;
  }
}

TEST_F(ContactWindowLanes, GatherAndGatherCommonGiveTheScalarLoopsBits) {
  constexpr int kN = 10;
  for (int trial = 0; trial < 2000; ++trial) {
    Points x(kN, 3), dx(kN, 3);
    for (int e = 0; e < x.size(); ++e) {
      x.data()[e] = Random();
      dx.data()[e] = Random();
    }
    const ContactWindow a{trial % (kN - 3), RandomWeights()};
    const ContactWindow b{(trial / 3) % (kN - 3), RandomWeights()};
    Vec3 ref = Vec3::Zero(), ref_dx = Vec3::Zero(), common = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      ref += a.w[i] * x.row(a.first + i).transpose();
      ref_dx += a.w[i] * (x.row(a.first + i) + dx.row(a.first + i)).transpose();
      common += a.w[i] * x.row(a.first + i).transpose() + b.w[i] * x.row(b.first + i).transpose();
    }
    const Vec3 got = a.Gather(x), got_dx = a.Gather(x, dx.data());
    const Vec3 got_common = GatherCommon(a, b, x.data());
    ASSERT_TRUE(SameBits(got.data(), ref.data(), 3)) << "trial " << trial;
    ASSERT_TRUE(SameBits(got_dx.data(), ref_dx.data(), 3)) << "trial " << trial;
    ASSERT_TRUE(SameBits(got_common.data(), common.data(), 3)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace viscera::mechanics
