#pragma once
/// Gauss-Legendre rules on [0, 1]. The n-point rule integrates polynomials of degree
/// 2n-1 exactly: 4 points are exact for products of two cubic basis functions (degree 6).
#include <array>

namespace viscera::spline {

template <int N>
struct GaussLegendre;

template <>
struct GaussLegendre<3> {
  static constexpr std::array<double, 3> kNodes = {0.1127016653792583, 0.5, 0.8872983346207417};
  static constexpr std::array<double, 3> kWeights = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
};

template <>
struct GaussLegendre<4> {
  static constexpr std::array<double, 4> kNodes = {0.0694318442029737, 0.3300094782075719,
                                                   0.6699905217924281, 0.9305681557970263};
  static constexpr std::array<double, 4> kWeights = {0.1739274225687269, 0.3260725774312731,
                                                     0.3260725774312731, 0.1739274225687269};
};

}  // namespace viscera::spline
