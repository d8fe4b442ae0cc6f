#pragma once
/// The Delassus matrix G = J W^-1 J^T of a set of contacts (a contact's normal speed per unit
/// impulse on another; W the impact limiter's M or the implicit system), filled incrementally:
/// both impulse solves grow their set round by round, keeping its order, so the entries of the
/// contacts kept from the last fill stand and only the new contacts' rows and columns are
/// filled in. Contact: anything with spheres a, b and a normal (ImpactLimiter::Contact).
/// Allocates only when a set larger than any before needs more room.
#include <algorithm>
#include <vector>

#include "common/types.h"

namespace viscera::mechanics {

template <typename Contact>
class IncrementalDelassus {
 public:
  /// Room for this many contacts before any allocation.
  void Reserve(size_t contacts) { filled_.reserve(contacts); }

  /// Forgets every entry: call when the columns behind them are solved again.
  void Reset() { filled_.clear(); }

  /// G for `contacts`: the leading contacts that are the same pairs with the same normals as at
  /// the last fill since Reset keep their entries; entry(i, j) (i <= j) gives the others.
  template <typename Entry>
  void Fill(const std::vector<Contact>& contacts, Entry&& entry) {
    const auto c = static_cast<Eigen::Index>(contacts.size());
    if (g_.rows() < c) {
      const Eigen::Index room = std::max<Eigen::Index>(c, 2 * g_.rows());
      g_.resize(room, room);  // loses the entries
      filled_.clear();
    }
    size_t kept = 0;
    while (kept < filled_.size() && kept < contacts.size() && Same(filled_[kept], contacts[kept]))
      ++kept;
    filled_.assign(contacts.begin(), contacts.end());  // grows with the high-water mark only
    for (auto j = static_cast<Eigen::Index>(kept); j < c; ++j) {
      for (Eigen::Index i = 0; i <= j; ++i) {
        const double g = entry(i, j);
        g_(i, j) = g;
        g_(j, i) = g;
      }
    }
  }

  /// At least contacts by contacts; its leading block is G (SolveContactImpulses reads it so).
  const MatX& matrix() const { return g_; }

 private:
  static bool Same(const Contact& x, const Contact& y) {
    return x.a == y.a && x.b == y.b && (x.normal.array() == y.normal.array()).all();
  }

  MatX g_;
  std::vector<Contact> filled_;  // the contacts whose entries g_ holds
};

}  // namespace viscera::mechanics
