#include "handscan/hokuyo/sensor_parameters.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

namespace handscan::hokuyo {

Result<SensorParameters> SensorParameters::fromPpReply(const ScipFrame& pp) {
    if (pp.command != "PP" || !pp.ok()) {
        return Status(StatusCode::kProtocolError,
                      "PP reply expected, got " + pp.command + " (" + pp.statusText() + ")");
    }
    SensorParameters p;
    p.model = pp.item("MODL").value_or("");
    struct Key {
        const char* name;
        int* field;
    };
    const Key keys[] = {{"DMIN", &p.dmin_mm}, {"DMAX", &p.dmax_mm}, {"ARES", &p.ares},
                        {"AMIN", &p.amin},    {"AMAX", &p.amax},    {"AFRT", &p.afrt},
                        {"SCAN", &p.scan_rpm}};
    for (const Key& k : keys) {
        const auto text = pp.item(k.name);
        if (!text) {
            return Status(StatusCode::kProtocolError, std::string("PP reply: no ") + k.name +
                                                          " line; the sensor is not SCIP 2.0 "
                                                          "compliant or the reply was cut");
        }
        // Values may carry a unit or comment after the number (e.g. "SCAN:2400" vs "2400[rpm]").
        const char* b = text->data();
        const auto [end, ec] = std::from_chars(b, b + text->size(), *k.field);
        if (ec != std::errc{} || end == b) {
            return Status(StatusCode::kProtocolError,
                          std::string("PP reply: ") + k.name + ":" + *text + " is not a number");
        }
    }
    if (p.ares <= 0 || p.scan_rpm <= 0 || p.amin < 0 || p.amax < p.amin || p.amax > 9999 ||
        p.dmax_mm <= p.dmin_mm) {
        return Status(StatusCode::kProtocolError,
                      "PP reply: inconsistent parameters (ARES " + std::to_string(p.ares) +
                          ", SCAN " + std::to_string(p.scan_rpm) + ", AMIN..AMAX " +
                          std::to_string(p.amin) + ".." + std::to_string(p.amax) + ", DMIN..DMAX " +
                          std::to_string(p.dmin_mm) + ".." + std::to_string(p.dmax_mm) + ")");
    }
    return p;
}

TimeNs SensorParameters::scanPeriodNs() const {
    return scan_rpm > 0 ? static_cast<TimeNs>(std::llround(60e9 / scan_rpm)) : 0;
}

double SensorParameters::stepPeriodNs() const {
    return scan_rpm > 0 && ares > 0 ? 60e9 / scan_rpm / ares : 0.0;
}

double SensorParameters::stepAngleRad() const {
    return ares > 0 ? 2.0 * std::numbers::pi / ares : 0.0;
}

double SensorParameters::angleRad(int step) const { return (step - afrt) * stepAngleRad(); }

}  // namespace handscan::hokuyo
