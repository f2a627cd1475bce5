#pragma once
// Points with outward normals sampled on the phantom shapes of the points tests (sphere,
// cube, cylinder, torus, cube minus a sphere at one corner), seeded.

#include <cmath>
#include <random>
#include <string>

#include "vdbmesh/points.h"

namespace vdbmesh::test {

inline PointCloud sample_shape(const std::string& shape, std::size_t count, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::normal_distribution<double> g(0.0, 1.0);
    PointCloud c;
    auto add = [&](Vec3d p, Vec3d n) {
        c.points.push_back(p);
        c.normals.push_back(n);
    };
    auto cube_face = [&](Vec3d& p, Vec3d& n) {  // the cube [-1, 1]^3
        const int face = int(std::uniform_int_distribution<int>(0, 5)(rng));
        const int axis = face / 2;
        const double side = face % 2 ? 1.0 : -1.0;
        p = {u(rng), u(rng), u(rng)};
        p[std::size_t(axis)] = side;
        n = {0, 0, 0};
        n[std::size_t(axis)] = side;
    };
    while (c.points.size() < count) {
        if (shape == "sphere") {
            Vec3d p{g(rng), g(rng), g(rng)};
            const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            for (double& x : p) x /= l;
            add(p, p);
        } else if (shape == "cube") {
            Vec3d p, n;
            cube_face(p, n);
            add(p, n);
        } else if (shape == "cylinder") {  // radius 1, z in [-1, 1]: side area 4 pi, caps 2 pi
            const double t = std::uniform_real_distribution<double>(0, 6 * M_PI)(rng);
            if (t < 4 * M_PI) {
                const double a = t / 2;
                add({std::cos(a), std::sin(a), u(rng)}, {std::cos(a), std::sin(a), 0});
            } else {
                const double x = u(rng), y = u(rng);
                if (x * x + y * y > 1) continue;
                const double z = t < 5 * M_PI ? 1.0 : -1.0;
                add({x, y, z}, {0, 0, z});
            }
        } else if (shape == "torus") {  // R = 1, r = 0.4, around z
            const double a = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
            const double b = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
            if (std::uniform_real_distribution<double>(0, 1.4)(rng) > 1 + 0.4 * std::cos(b)) continue;  // area weight
            const Vec3d n{std::cos(b) * std::cos(a), std::cos(b) * std::sin(a), std::sin(b)};
            add({(1 + 0.4 * std::cos(b)) * std::cos(a), (1 + 0.4 * std::cos(b)) * std::sin(a), 0.4 * std::sin(b)}, n);
        } else if (shape == "cube_minus_sphere") {  // a ball of radius 0.9 around (1, 1, 1) removed
            const Vec3d o{1, 1, 1};
            const double r = 0.9;
            // Cube faces 24 area, the spherical cap inside the cube: an eighth of 4 pi r^2.
            const double cap = 0.5 * M_PI * r * r;
            if (std::uniform_real_distribution<double>(0, 24 + cap)(rng) < 24) {
                Vec3d p, n;
                cube_face(p, n);
                const double d2 = (p[0] - 1) * (p[0] - 1) + (p[1] - 1) * (p[1] - 1) + (p[2] - 1) * (p[2] - 1);
                if (d2 < r * r) continue;
                add(p, n);
            } else {
                Vec3d d{-std::abs(g(rng)), -std::abs(g(rng)), -std::abs(g(rng))};
                const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                for (double& x : d) x /= l;
                add({o[0] + r * d[0], o[1] + r * d[1], o[2] + r * d[2]}, {-d[0], -d[1], -d[2]});
            }
        } else {
            throw std::invalid_argument("unknown shape " + shape);
        }
    }
    return c;
}

}  // namespace vdbmesh::test
