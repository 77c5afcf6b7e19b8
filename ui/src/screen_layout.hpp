// Where things go on the screen, in window pixels from the top-left: a status bar across the
// top, the button column on the right, the 3D view in the rest. Sizes scale with the window so
// that buttons stay finger-sized on a 7" 1024x600 panel and on a desktop window.
#pragma once

#include <algorithm>

namespace handscan::ui {

struct Rect {
    float x = 0, y = 0, w = 0, h = 0;
};

struct ScreenLayout {
    Rect status_bar, buttons, view;
    float scale = 1.0f;  // font / button scale relative to a 800 px high window

    static ScreenLayout compute(float width, float height) {
        ScreenLayout l;
        l.scale = std::clamp(height / 800.0f, 0.6f, 2.0f);
        const float bar_h = 110.0f * l.scale;
        const float panel_w = std::min(260.0f * l.scale, width * 0.35f);
        l.status_bar = {0, 0, width, bar_h};
        l.buttons = {width - panel_w, bar_h, panel_w, height - bar_h};
        l.view = {0, bar_h, width - panel_w, height - bar_h};
        return l;
    }
};

}  // namespace handscan::ui
