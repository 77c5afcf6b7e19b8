// Saves the current framebuffer as a PNG (tests, documentation figures, support).
#pragma once

#include <string>

#include "handscan/core/status.hpp"

namespace handscan::ui {

// Reads the back buffer (width x height) of the current context and writes it to `path`.
[[nodiscard]] Status saveFramebufferPng(const std::string& path, int width, int height);

}  // namespace handscan::ui
