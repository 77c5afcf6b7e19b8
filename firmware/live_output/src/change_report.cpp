#include "handscan/live_output/change_report.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace handscan::live_output {

shm::ChangeReport toChangeReport(std::span<const localize::ChangeCell> cells, double cell_m) {
    shm::ChangeReport r;
    r.cell_m = static_cast<float>(cell_m);
    std::vector<std::size_t> order(cells.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    // The clearest changes first (most points), in the localizer's order among equals.
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return cells[a].points > cells[b].points;
    });
    for (std::size_t i : order) {
        const localize::ChangeCell& c = cells[i];
        const bool appeared = c.kind == localize::ChangeKind::kAppeared;
        ++(appeared ? r.appeared : r.vanished);
        if (r.count == shm::kMaxChangeCells) continue;
        shm::ChangeCellRecord& to = r.cells[r.count++];
        to.x_m = static_cast<float>(c.centre.x());
        to.y_m = static_cast<float>(c.centre.y());
        to.z_m = static_cast<float>(c.centre.z());
        to.points = static_cast<std::uint32_t>(std::min<std::uint64_t>(c.points, UINT32_MAX));
        to.kind = static_cast<std::uint8_t>(appeared ? shm::ChangeKind::kAppeared
                                                     : shm::ChangeKind::kVanished);
    }
    return r;
}

}  // namespace handscan::live_output
