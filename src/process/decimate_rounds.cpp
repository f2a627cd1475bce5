// The Decimator's rounds (process/decimator.h): the cheapest edges taken, those apart chosen,
// the triangle grids built, the plans checked in parallel, the crossings between their new stars
// found, and the plans applied in order of cost (the overview is in decimate_mesh.cpp).
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "process/decimator.h"

namespace vdbmesh::detail::decimation {

constexpr std::size_t kMinRound = 64;  ///< candidates a round takes at least
/// ... and at least this share of the triangles: near the target a round applies only about a
/// fifth of the few collapses still wanted, and every round costs passes over the whole mesh
/// (CThead: 38 rounds without, 19 with, the largest quadric error 1% higher).
constexpr std::size_t kMinRoundDivisor = 32;

Mesh Decimator::run(DecimateReport& report) {
    gather_quadrics();
    measure_components();
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(triangles_.size()), 4096), [&](const auto& range) {
        for (std::uint32_t t = range.begin(); t != range.end(); ++t) refresh(t);
    });
    tbb::enumerable_thread_specific<Scratch> scratch;
    std::vector<Candidate> candidates;
    std::vector<Plan> plans;
    Scratch own;
    own.mark.assign(positions_.size(), 0);
    while (alive_count_ > target_) {
        tbb::parallel_sort(dirty_.begin(), dirty_.end());  // (in memory order, as the checks below)
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, dirty_.size(), 1024), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                if (i + 8 < range.end()) {
                    const Ids& ahead = triangles_[dirty_[i + 8] / 3];
                    for (const std::uint32_t v : ahead) __builtin_prefetch(&quadrics_[v]), __builtin_prefetch(&quadrics_[v].d2), __builtin_prefetch(&positions_[v]);
                }
                refresh(dirty_[i] / 3, dirty_[i]);
            }
        });
        for (const std::uint32_t c : dirty_) {
            const std::uint32_t t = c / 3;
            if (!moved_[t]) moved_[t] = 1, moved_list_.push_back(t);
        }
        dirty_.clear();
        // The cheapest, about as many as the collapses still wanted (and never very few); with
        // under a quarter of the triangles to go, four times as many: about a third of them
        // are chosen and pass, so a round then makes about all the collapses wanted, where
        // as many would leave a tail of rounds that each pass over the whole mesh for a few
        // collapses (bunny: 16 rounds -> 14, 0.1 s of 3.8; the mean distance to the input +1%).
        const std::size_t collapses = (alive_count_ - target_ + 1) / 2;
        const std::size_t wanted = alive_count_ - target_ < alive_count_ / 4 ? 4 * collapses : collapses;
        const std::size_t take = std::max({kMinRound, wanted, alive_count_ / kMinRoundDivisor});
        if (gather_cheap(candidates, take) == 0) break;
        // The grids the checks read are built beside the sorting and the choice (mostly
        // sequential), which read neither them nor what building them writes.
        tbb::task_group grids;
        grids.run([&] { build_triangle_grids(); });
        keep_cheapest(candidates, take);
        choose_apart(candidates, plans, ring_corners_, own);
        grids.wait();
        // Checked in the order of their triangles, which keeps neighbours together in memory
        // (the checks are independent of each other; the cost order scatters them).
        std::vector<std::uint32_t> in_place(plans.size());
        for (std::uint32_t i = 0; i < plans.size(); ++i) in_place[i] = i;
        tbb::parallel_sort(in_place.begin(), in_place.end(), [&](std::uint32_t i, std::uint32_t j) { return plans[i].corner < plans[j].corner; });
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, plans.size(), 256), [&](const auto& range) {
            Scratch& s = scratch.local();
            for (std::size_t n = range.begin(); n != range.end(); ++n) {
                // (in cost order the plans lie anywhere: each asked for 24 ahead, its star's
                // triangles 16 ahead, their corners' points 8 ahead)
                if (n + 24 < range.end()) __builtin_prefetch(&plans[in_place[n + 24]], 1);
                if (n + 16 < range.end()) for_star(plans[in_place[n + 16]], [&](const Ids& t) { __builtin_prefetch(&t); });
                if (n + 8 < range.end()) {
                    for_star(plans[in_place[n + 8]], [&](const Ids& t) {
                        for (const std::uint32_t v : t) __builtin_prefetch(&positions_[v]);
                    });
                }
                plans[in_place[n]].verdict = check(plans[in_place[n]], s);
            }
        });
        find_crossings(plans, in_place, scratch);
        apply_round(plans, report);
    }
    return compact();
}

/// The candidates, in order of cost, whose ends lie in the star of no earlier one chosen.
/// Then no collapse of the round changes the rings of another's ends or the triangles of its
/// star (a triangle changes only if it has an end of the collapse, and a vertex's ring only
/// if it is in the star), which is what the link condition and the geometry check read.
/// Each plan's corners round its ends go to @a rings (the checks read them from there without
/// walking the rings again, a chain of loads). The rings are walked a batch of candidates at a
/// time, side by side (many chains of loads in flight, not one): the next ones whose ends no
/// earlier choice has marked, then chosen in order as before (one may yet be marked by one
/// chosen before it in the batch; its walk is then wasted).
void Decimator::choose_apart(const std::vector<Candidate>& candidates, std::vector<Plan>& plans, std::vector<std::uint32_t>& rings, Scratch& s) const {
    plans.clear(), rings.clear();
    if (++s.stamp == 0) std::fill(s.mark.begin(), s.mark.end(), 0), s.stamp = 1;
    const std::uint8_t stamp = s.stamp;
    const auto marked = [&](std::uint32_t corner) { return s.mark[vertex(next(corner))] == stamp || s.mark[vertex(prev(corner))] == stamp; };
    constexpr std::size_t kBatch = 32;
    s.walks.resize(kBatch);
    for (std::size_t n = 0; n < candidates.size();) {
        std::size_t size = 0;
        for (; n < candidates.size() && size < kBatch; ++n) {
            // (in cost order the candidates lie anywhere: their triangles and those triangles'
            // opposite corners asked for 16 ahead, then their ends' marks 8 ahead)
            if (n + 16 < candidates.size()) {
                const std::uint32_t ahead = candidates[n + 16].corner;
                __builtin_prefetch(&triangles_[ahead / 3]), __builtin_prefetch(&opposite_[ahead - ahead % 3]);
            }
            if (n + 8 < candidates.size()) {
                const std::uint32_t ahead = candidates[n + 8].corner;
                for (const std::uint32_t v : {vertex(next(ahead)), vertex(prev(ahead))}) __builtin_prefetch(&s.mark[v]);
            }
            if (!marked(candidates[n].corner)) s.walks[size++].corner = candidates[n].corner;
        }
        walk_rings(s.walks.data(), size);
        for (std::size_t k = 0; k < size; ++k) {
            const Walk& walk = s.walks[k];
            if (marked(walk.corner)) continue;
            Plan plan;
            plan.corner = walk.corner;
            plan.ring_begin = std::uint32_t(rings.size());
            for (int end = 0; end < 2; ++end) {
                plan.around[end] = std::uint32_t(walk.around[end].size());
                for (const std::uint32_t c : walk.around[end]) s.mark[vertex(next(c))] = stamp, rings.push_back(c);
            }
            plans.push_back(plan);
        }
    }
}

/// The corners round both ends of each of @a walks, from the edge's own triangle, all walked
/// side by side.
void Decimator::walk_rings(Walk* walks, std::size_t size) const {
    std::size_t walking = 0;
    for (std::size_t k = 0; k < size; ++k) {
        Walk& walk = walks[k];
        for (int end = 0; end < 2; ++end) walk.around[end].clear(), walk.at[end] = walk.first(end);
        walking += 2;
    }
    while (walking > 0) {
        for (std::size_t k = 0; k < size; ++k) {
            Walk& walk = walks[k];
            for (int end = 0; end < 2; ++end) {
                std::vector<std::uint32_t>& around = walk.around[end];
                if (!around.empty() && walk.at[end] == walk.first(end)) continue;
                around.push_back(walk.at[end]);
                __builtin_prefetch(&triangles_[walk.at[end] / 3]);  // (its neighbour is marked once chosen)
                walk.at[end] = swing(walk.at[end]);
                walking -= walk.at[end] == walk.first(end);
            }
        }
    }
}

/// The alive triangles with their boxes, in cells of kCellEdges mean extents: those that
/// moved since the settled grid was built in a grid of their own, rebuilt each round; the
/// settled grid rebuilt only once a quarter of the triangles has moved.
void Decimator::build_triangle_grids() {
    const auto dead = [&](std::uint32_t t) { return alive_[t] == 0; };
    const bool all = settled_grid_.empty() || moved_list_.size() > alive_count_ / 4;
    if (all) {
        for (const std::uint32_t t : moved_list_) moved_[t] = 0;
        moved_list_.clear();
        if (alive_list_.empty()) alive_list_.resize(triangles_.size()), std::iota(alive_list_.begin(), alive_list_.end(), 0u);
        alive_list_.erase(std::remove_if(alive_list_.begin(), alive_list_.end(), dead), alive_list_.end());
    } else {
        moved_list_.erase(std::remove_if(moved_list_.begin(), moved_list_.end(), dead), moved_list_.end());
    }
    const std::vector<std::uint32_t>& ids = all ? alive_list_ : moved_list_;
    const auto box_of = [&](std::size_t i) { return boxes_[ids[i]]; };
    const auto payload_of = [&](std::size_t i) { return GridTriangle{ids[i], summaries_[ids[i]]}; };
    if (!all) {
        moved_grid_.build(ids.size(), box_of, payload_of);
        return;
    }
    // (the settled grid over the box of the first triangles: the collapses keep to it but by
    // a little, and the pass over all boxes for theirs is spared)
    if (holds_nothing(domain_)) {
        for (std::size_t i = 0; i < ids.size(); ++i) grow(domain_, box_of(i).lo), grow(domain_, box_of(i).hi);
    }
    settled_grid_.build(ids.size(), box_of, payload_of, &domain_);
    moved_grid_.build(0, [](std::size_t) { return empty_box(); }, [](std::size_t) { return GridTriangle{}; });
}

/// For each plan that passed its checks, the earlier ones that did too and whose new stars
/// cross its own: no plan's ends are in another's star, so each check still holds but for
/// the new triangles of two collapses of the round, which no check has met. Both new stars
/// are as the checks built them from the mesh at the start of the round: no other collapse
/// of the round changes them (their vertices are neither collapse's ends nor its ends'
/// neighbours; two stars may share link vertices, which the exact tests allow for).
/// @a in_place: the plans in the order to visit them (any order gives the same crossings).
void Decimator::find_crossings(std::vector<Plan>& plans, const std::vector<std::uint32_t>& in_place,
                               tbb::enumerable_thread_specific<Scratch>& scratch) {
    plan_grid_.build(
        plans.size(), [&](std::size_t i) { return plans[i].verdict == Verdict::passed ? plans[i].star : empty_box(); },
        [&](std::size_t i) { return GridPlan{std::uint32_t(i), plans[i].fan}; });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in_place.size(), 64), [&](const auto& range) {
        Scratch& s = scratch.local();
        for (std::size_t n = range.begin(); n != range.end(); ++n) {
            if (n + 8 < range.end()) __builtin_prefetch(&plans[in_place[n + 8]]);  // (in cost order: anywhere)
            const std::uint32_t i = in_place[n];
            Plan& p = plans[i];
            if (p.verdict != Verdict::passed) continue;
            p.crossed.clear();
            if (apart_from_all(p)) continue;
            bool star_ready = false;
            plan_grid_.visit(p.star, [&](const GridPlan& entry, const Box&) {
                const std::uint32_t j = entry.plan;
                if (j >= i) return true;
                if (!star_ready) {
                    s.ids.clear(), s.corners.clear(), s.boxes.clear();
                    for_new_star(p, [&](std::uint32_t, const Ids& ids, const FloatTriangle& points, const Box& box) {
                        s.ids.push_back(ids), s.corners.push_back(to_double(points)), s.boxes.push_back(box);
                        return true;
                    });
                    prepare_star(s);
                    star_ready = true;
                }
                if (crosses_new_star(plans[j], p.star, s)) p.crossed.push_back(j);
                return true;
            });
        }
    });
}

/// Whether @a p's new star certainly crosses no other of the round, whichever of them apply
/// before it: the directions its check found faced in its region are also faced by the new
/// stars of all passed plans near it, of its component (so the mesh as it is when p applies,
/// the round's start but for those stars, meets intersection_free()'s condition). The plan
/// grid's cells tell first what the stars in them have in common; failing that, the stars met.
bool Decimator::apart_from_all(const Plan& p) const {
    if (!p.apart.clears()) return false;
    Summary in_cells = p.apart;
    in_cells.add(plan_grid_.summary(p.region));
    if (in_cells.clears()) return true;
    Summary met = p.apart;
    plan_grid_.visit(p.region, [&](const GridPlan& q, const Box&) { return met.add(q.summary), met.clears(); });
    return met.clears();
}

/// Whether a triangle of the new star in @a s (whose box is @a star) crosses one of the new
/// star of plan @a q (neither holds the other's kept vertex).
bool Decimator::crosses_new_star(const Plan& q, const Box& star, const Scratch& s) const {
    return !for_new_star(q, [&](std::uint32_t, const Ids& ids, const FloatTriangle& points, const Box& box) {
        if (!detail::boxes_overlap(star, box)) return true;
        const detail::PreparedTriangle corners(to_double(points));
        return s.box_columns.for_meeting(box, [&](std::size_t i) { return !detail::triangles_intersect(s.ids[i], s.prepared[i], ids, corners); });
    });
}

/// Applies the plans that passed their checks, in order of cost, while triangles are to go;
/// a plan whose new star crosses that of one applied before waits for the next round. The
/// cost order decides which apply; they are then applied in the order of their triangles
/// (neighbours together in memory), side by side: their stars share no triangle, so no
/// collapse reads or writes what another writes but vertex_corner_ at a link vertex two
/// stars share, which is set after, in that order.
void Decimator::apply_round(const std::vector<Plan>& plans, DecimateReport& report) {
    std::vector<char> applied(plans.size(), 0);
    std::vector<std::uint32_t> chosen;
    std::size_t alive = alive_count_;
    for (std::uint32_t i = 0; i < plans.size() && alive > target_; ++i) {
        const Plan& p = plans[i];
        if (p.verdict != Verdict::passed) {
            rejected_[p.corner] = 1;
            ++(p.verdict == Verdict::topology ? report.rejected_topology
               : p.verdict == Verdict::geometry ? report.rejected_geometry
                                                : report.rejected_intersection);
            continue;
        }
        if (std::any_of(p.crossed.begin(), p.crossed.end(), [&](std::uint32_t j) { return applied[j] != 0; })) continue;
        double& volume = volume_[p.fan.component];
        if (volume != 0 && (volume + p.volume_change) * volume <= 0) {  // the component would turn inside out
            rejected_[p.corner] = 1;
            ++report.rejected_geometry;
            continue;
        }
        volume += p.volume_change;
        applied[i] = 1;
        chosen.push_back(p.corner);
        alive -= 2;
    }
    tbb::parallel_sort(chosen.begin(), chosen.end());
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> dirty;
    tbb::enumerable_thread_specific<double> max_error(0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chosen.size(), 256), [&](const auto& range) {
        std::vector<std::uint32_t>& local = dirty.local();
        double& largest = max_error.local();
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            largest = std::max(largest, error_[chosen[i]]);
            if (i + 8 < range.end()) {  // (the ends' quadrics are read at random)
                const std::uint32_t ahead = chosen[i + 8];
                for (const std::uint32_t v : {vertex(next(ahead)), vertex(prev(ahead))}) __builtin_prefetch(&quadrics_[v], 1), __builtin_prefetch(&vertex_corner_[v], 1);
            }
            apply(chosen[i], local);
        }
    });
    for (const std::uint32_t corner : chosen) name_opposite_corners(corner);
    for (const double error : max_error) report.max_error = std::max(report.max_error, std::sqrt(error));
    report.collapses += chosen.size();
    alive_count_ -= 2 * chosen.size();
    for (const std::vector<std::uint32_t>& local : dirty) dirty_.insert(dirty_.end(), local.begin(), local.end());  // (sorted before use)
}

}  // namespace vdbmesh::detail::decimation
