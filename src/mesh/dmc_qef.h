#pragma once
// Private: the 4D quadratic error function of Dual Marching Cubes (project source 000_*.txt,
// section 2.1.1; Schaefer and Warren 2004). At a sample x_i with value f_i and gradient g_i
// the graph w = f(x) has the tangent hyperplane w = f_i + g_i . (x - x_i); a point (x, w) is
// charged (g_i . (x - x_i) + f_i - w)^2 / (1 + |g_i|^2). The QEF keeps the 5x5 symmetric
// matrix [A -b]^T [A -b] (A^T A, A^T b, b^T b), so QEFs of children simply add.

#include <array>

#include "mesh/edge_crossing.h"

namespace vdbmesh::detail {

class Qef4 {
public:
    /// Adds the tangent hyperplane at sample @a x (value @a f, gradient @a g).
    void add_sample(const Point3d& x, double f, const Point3d& g);
    void add(const Qef4& other);

    struct Solution {
        Point3d position;
        double value;
        double error;  ///< the QEF at the solution
    };
    /// The minimiser, found around the mass point with a truncated pseudo-inverse (directions
    /// the samples do not determine stay at the mass point), kept inside the box [lo, hi]:
    /// a minimiser outside is clamped and its value re-optimised.
    Solution solve(const Point3d& lo, const Point3d& hi) const;

    int count() const { return count_; }

private:
    double evaluate(const std::array<double, 4>& y) const;

    std::array<double, 15> m_{};  ///< upper triangle of the 5x5 matrix, row by row
    std::array<double, 4> mass_{};  ///< sum of (x_i, f_i)
    int count_ = 0;
};

}  // namespace vdbmesh::detail
