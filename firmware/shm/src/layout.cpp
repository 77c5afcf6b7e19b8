// Names of the protocol's enumerations (logs, UI, CLI).
#include "handscan/shm/layout.hpp"

namespace handscan::shm {

const char* toString(CommandType type) {
    switch (type) {
        case CommandType::kNone:
            return "none";
        case CommandType::kStartScan:
            return "start-scan";
        case CommandType::kStopScan:
            return "stop-scan";
        case CommandType::kNewScan:
            return "new-scan";
        case CommandType::kExport:
            return "export";
        case CommandType::kShutdown:
            return "shutdown";
        case CommandType::kContinueScan:
            return "continue-scan";
        case CommandType::kCalibrate:
            return "calibrate";
    }
    return "unknown";
}

const char* toString(CommandState state) {
    switch (state) {
        case CommandState::kPending:
            return "pending";
        case CommandState::kAccepted:
            return "accepted";
        case CommandState::kInProgress:
            return "in progress";
        case CommandState::kDone:
            return "done";
        case CommandState::kFailed:
            return "failed";
        case CommandState::kRejected:
            return "rejected";
    }
    return "unknown";
}

const char* toString(ScanState state) {
    switch (state) {
        case ScanState::kIdle:
            return "idle";
        case ScanState::kScanning:
            return "scanning";
        case ScanState::kStopped:
            return "stopped";
    }
    return "unknown";
}

const char* toString(LocalizationState state) {
    switch (state) {
        case LocalizationState::kNone:
            return "none";
        case LocalizationState::kSearching:
            return "searching";
        case LocalizationState::kLocked:
            return "locked";
        case LocalizationState::kNotLocked:
            return "not locked";
    }
    return "unknown";
}

const char* toString(ChangeKind kind) {
    switch (kind) {
        case ChangeKind::kNone:
            return "none";
        case ChangeKind::kAppeared:
            return "appeared";
        case ChangeKind::kVanished:
            return "vanished";
    }
    return "unknown";
}

bool isFinal(CommandState state) {
    return state == CommandState::kDone || state == CommandState::kFailed ||
           state == CommandState::kRejected;
}

}  // namespace handscan::shm
