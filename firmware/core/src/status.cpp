#include "handscan/core/status.hpp"

namespace handscan {

const char* toString(StatusCode code) {
    switch (code) {
        case StatusCode::kOk:
            return "ok";
        case StatusCode::kInvalidArgument:
            return "invalid argument";
        case StatusCode::kChecksumError:
            return "checksum error";
        case StatusCode::kProtocolError:
            return "protocol error";
        case StatusCode::kTimeout:
            return "timeout";
        case StatusCode::kDisconnected:
            return "disconnected";
        case StatusCode::kDeviceError:
            return "device error";
        case StatusCode::kIoError:
            return "I/O error";
        case StatusCode::kNotFound:
            return "not found";
        case StatusCode::kTruncated:
            return "truncated";
        case StatusCode::kUnsupported:
            return "unsupported";
        case StatusCode::kNoSpace:
            return "no space left";
    }
    return "unknown";
}

}  // namespace handscan
