#include "inside_side.h"

#include <cstdint>

namespace vdbmesh::python {

namespace {

/// (samples above @a level, samples below it) on the faces of @a box, each counted once.
std::pair<std::int64_t, std::int64_t> border_votes(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box,
                                                    double level) {
    auto accessor = grid.getConstAccessor();
    std::int64_t above = 0, below = 0;
    const auto vote = [&](const openvdb::Coord& ijk) {
        const double value = accessor.getValue(ijk);
        above += value > level;
        below += value < level;
    };
    const openvdb::Coord lo = box.min(), hi = box.max();
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y) {
            if (z == lo.z() || z == hi.z() || y == lo.y() || y == hi.y()) {
                for (int x = lo.x(); x <= hi.x(); ++x) vote({x, y, z});
            } else {
                vote({lo.x(), y, z});
                if (hi.x() != lo.x()) vote({hi.x(), y, z});
            }
        }
    return {above, below};
}

}  // namespace

Inside inside_away_from_border(const openvdb::FloatGrid& grid, double level) {
    const auto box = stored_scan_box(grid);
    if (!box) {
        if (grid.getGridClass() == openvdb::GRID_LEVEL_SET) return Inside::below;
        return grid.background() > level ? Inside::below : Inside::above;
    }
    const auto [above, below] = border_votes(grid, *box, level);
    return above > below ? Inside::below : Inside::above;
}

}  // namespace vdbmesh::python
