// Spacing fields q(x): the desired node spacing everywhere in the domain.
// BoundarySpacing is thesis eq. 3.6 (inverse-distance weighting of the closest segment of each
// curve); ExpressionSpacing evaluates a user expression in x and y (muParser), e.g. eq. 7.2.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry_tree.hpp"

namespace pdmesh {

class SpacingField {
 public:
  virtual ~SpacingField() = default;
  virtual double at(Vec2 p) const = 0;
  // Evaluates many points (the simulation's spacing update); the default loops over at().
  virtual void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const;
  // at_many for points that move a little between calls: `guesses` is the caller's per-point memory
  // for the field (resized to p.size(), kept between calls). The same values; the default ignores it.
  virtual void at_many_guessed(const std::vector<Vec2>& p, std::vector<double>& q, std::vector<int>& guesses) const;
};

// The fewest lookups worth a thread in a thread-safe field's at_many (parallel_for's min_chunk):
// below that a thread costs more than it saves.
inline constexpr std::size_t kPointsPerThread = 4096;
// The same for fields that evaluate muParser expressions: an evaluation costs more than a lookup, so
// fewer points repay a thread.
inline constexpr std::size_t kExpressionPointsPerThread = 256;

// q(x) = sum_s (l_s / d_s) / sum_s (1 / d_s) over the closest segment s of each curve (eq. 3.6);
// on the boundary (some d_s == 0 exactly) the limit: the mean l_s of the curves at distance 0.
// at() is thread-safe. Keeps a reference to the tree, which must outlive it. See docs/spacing.md.
class BoundarySpacing final : public SpacingField {
 public:
  explicit BoundarySpacing(const GeometryTree& tree);
  double at(Vec2 p) const override;
  // The same values as at() per point, computed on up to kMaxThreads threads for large batches.
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override;
  static constexpr std::size_t kMaxThreads = 8;

 private:
  const GeometryTree& tree_;
};

// q(x, y) from an expression; throws InputError naming the expression on a syntax error
// or when it does not evaluate to a finite positive number. Variables x, y; constant pi.
// at() is not thread-safe (it drives one muParser instance); at_many() gives at()'s values on several
// threads, each with a parser of its own.
class ExpressionSpacing final : public SpacingField {
 public:
  explicit ExpressionSpacing(const std::string& expression);
  ~ExpressionSpacing() override;
  double at(Vec2 p) const override;
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pdmesh
