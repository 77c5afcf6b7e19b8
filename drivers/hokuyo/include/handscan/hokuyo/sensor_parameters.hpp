// The sensor's own description of itself, read from its PP / VV / II replies rather than
// hard-coded: reporting limits (DMIN, DMAX), angular resolution (ARES steps per revolution), the
// usable step range (AMIN..AMAX), the front step (AFRT) and the mirror speed (SCAN, rpm). The
// UTM-30LX-EW reports 23 mm..60 m, 1440 steps/rev, steps 0..1080, front 540, 2400 rpm.
#pragma once

#include <string>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/hokuyo/scip_stream_parser.hpp"

namespace handscan::hokuyo {

struct SensorParameters {
    std::string model;  // MODL
    int dmin_mm = 0;    // DMIN: smaller values are error codes
    int dmax_mm = 0;    // DMAX
    int ares = 0;       // ARES: steps per full revolution of the mirror
    int amin = 0;       // AMIN: first measurable step
    int amax = 0;       // AMAX: last measurable step
    int afrt = 0;       // AFRT: step that looks straight ahead (+x of the laser frame)
    int scan_rpm = 0;   // SCAN: mirror speed

    // Parses a PP reply; every key above must be present and sane.
    static Result<SensorParameters> fromPpReply(const ScipFrame& pp);

    TimeNs scanPeriodNs() const;  // one mirror revolution (25 ms at 2400 rpm)
    double stepPeriodNs() const;  // time between adjacent steps: 60 s / rpm / ARES
    double stepAngleRad() const;  // 2 pi / ARES
    // Beam angle of a step: (step - AFRT) * 2 pi / ARES, counter-clockwise positive.
    double angleRad(int step) const;
};

// VV and II: who the sensor is and how it feels.
struct SensorIdentity {
    std::string vendor;    // VV VEND
    std::string product;   // VV PROD
    std::string firmware;  // VV FIRM
    std::string protocol;  // VV PROT
    std::string serial;    // VV SERI
    std::string status;    // II STAT
};

}  // namespace handscan::hokuyo
