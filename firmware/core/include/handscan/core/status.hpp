// Errors on real-time paths: a [[nodiscard]] Status or Result<T> instead of exceptions (as MCAP's
// C++ library does). Exceptions are for start-up and configuration only.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace handscan {

enum class StatusCode {
    kOk = 0,
    kInvalidArgument,
    kChecksumError,
    kProtocolError,
    kTimeout,
    kDisconnected,
    kDeviceError,
    kIoError,
    kNotFound,
    kTruncated,
    kUnsupported,
    kNoSpace,
};

const char* toString(StatusCode code);

class [[nodiscard]] Status {
public:
    Status() = default;
    Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
    static Status ok() { return {}; }

    bool isOk() const { return code_ == StatusCode::kOk; }
    explicit operator bool() const { return isOk(); }
    StatusCode code() const { return code_; }
    const std::string& message() const { return message_; }

private:
    StatusCode code_ = StatusCode::kOk;
    std::string message_;
};

// A value or the Status explaining why there is none (std::expected arrives in C++23).
template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}         // NOLINT(google-explicit-constructor)
    Result(Status status) : v_(std::move(status)) {}  // NOLINT(google-explicit-constructor)

    bool isOk() const { return std::holds_alternative<T>(v_); }
    explicit operator bool() const { return isOk(); }
    T& value() & { return std::get<T>(v_); }
    const T& value() const& { return std::get<T>(v_); }
    T&& value() && { return std::get<T>(std::move(v_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() { return value(); }
    const T& operator*() const { return value(); }
    Status status() const { return isOk() ? Status::ok() : std::get<Status>(v_); }

private:
    std::variant<T, Status> v_;
};

}  // namespace handscan
