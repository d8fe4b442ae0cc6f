#pragma once
/// Nearest-rank quantiles for the timing figures (step cost, jitter, round trip).
#include <algorithm>
#include <cmath>
#include <vector>

namespace viscera {

/// The p-quantile (0 < p <= 1) of values[0..n): the ceil(p n)-th smallest. Reorders `values`
/// (nth_element, O(n)). 0 when n is 0.
inline double Quantile(double* values, int n, double p) {
  if (n <= 0) return 0.0;
  const int k = std::clamp(static_cast<int>(std::ceil(p * n)) - 1, 0, n - 1);
  std::nth_element(values, values + k, values + n);
  return values[k];
}

/// Same on a copy.
inline double Quantile(std::vector<double> values, double p) {
  return Quantile(values.data(), static_cast<int>(values.size()), p);
}

}  // namespace viscera
