// The change report of a scan continuing an earlier one (localize::Localizer::changes(): where
// something appeared or vanished between the sessions) as the live map publishes it for the
// touch screen: every cell counted, at most shm::kMaxChangeCells of them carried, those with the
// most points (the clearest changes) when there are more.
#pragma once

#include <span>

#include "handscan/localize/localizer.hpp"
#include "handscan/shm/layout.hpp"

namespace handscan::live_output {

shm::ChangeReport toChangeReport(std::span<const localize::ChangeCell> cells, double cell_m);

}  // namespace handscan::live_output
