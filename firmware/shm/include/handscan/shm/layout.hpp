// The live-map shared-memory protocol: the byte layout of the region that the pipeline daemon (or
// `handscan replay --live`, or `handscan shm-demo`) writes and any number of UI processes read.
// Every struct here is trivially copyable POD with fixed-size arrays and no pointers (as iceoryx's
// topics are), so the same bytes mean the same thing in every process. Nobody holds a lock across
// processes: single-writer sections are seqlocks (an even/odd counter around the payload), the
// point map and trajectory are append-only arrays published by a release-stored count, and the
// command slots (many UIs, one pipeline) are claimed with a compare-and-swap. Bump
// kLayoutVersion whenever a byte of this file changes meaning.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace handscan::shm {

inline constexpr std::uint64_t kMagic = 0x314D48534E435348ull;  // "HSCNSHM1" little-endian
inline constexpr std::uint32_t kLayoutVersion = 6;
inline constexpr const char* kDefaultRegionName = "/handscan-live";

inline constexpr std::size_t kPoseRingCapacity = 2048;  // > 10 s of 200 Hz poses
inline constexpr std::size_t kTrackCapacity = 65536;    // decimated trajectory of the whole scan
inline constexpr std::size_t kMaxSensors = 8;
inline constexpr std::size_t kMaxModules = 8;
inline constexpr std::size_t kCommandSlots = 16;
inline constexpr std::size_t kNameChars = 16;
inline constexpr std::size_t kTextChars = 120;
inline constexpr std::size_t kArgumentChars = 248;
inline constexpr std::size_t kCalibrationValues = 8;
// Change cells published for a continued scan: the largest this many (a few kB, copied whole at
// the localizer's 0.5 Hz; a changed building shows tens).
inline constexpr std::size_t kMaxChangeCells = 256;
// Scans on the device listed for "continue scan" (the newest this many).
inline constexpr std::size_t kMaxListedScans = 24;

// DOF order of every per-DOF mask: bit 0..2 rotation about x, y, z; bit 3..5 translation x, y, z
// (the (rot, trans) order of PoseEstimate::covariance).
inline constexpr int kDofCount = 6;
inline constexpr const char* kDofNames[kDofCount] = {"rx", "ry", "rz", "tx", "ty", "tz"};

enum class WriterState : std::uint64_t { kInitialising = 0, kRunning = 1, kClosed = 2 };
enum class ScanState : std::uint8_t { kIdle = 0, kScanning = 1, kStopped = 2 };
enum class ModuleState : std::uint8_t { kOff = 0, kActive = 1, kBypassed = 2 };
enum class ExportState : std::uint8_t { kIdle = 0, kRunning = 1, kDone = 2, kFailed = 3 };
enum class CalibrationState : std::uint8_t { kIdle = 0, kRunning = 1, kDone = 2, kFailed = 3 };
enum class CommandType : std::uint32_t {
    kNone = 0,
    kStartScan = 1,
    kStopScan = 2,
    kNewScan = 3,
    kExport = 4,
    kShutdown = 5,
    // Continue an earlier scan (section 9): a new scan localized on it. Argument: optional
    // "scan=NAME" (a directory of the journal root; default: the stopped scan, else the newest
    // that can be continued) and "pose=x,y,z,qx,qy,qz,qw" (where the operator stands, in that
    // scan's frame, TUM order), separated by a space.
    kContinueScan = 6,
    kCalibrate = 7,  // self-calibrate on the last scan's raw recording (argument: "" or rounds=N)
};
// A scan continuing an earlier one: finding its place on the earlier map, found, or not found
// by the last search (walk to where the earlier scan started, or place yourself on its map).
enum class LocalizationState : std::uint8_t {
    kNone = 0,
    kSearching = 1,
    kLocked = 2,
    kNotLocked = 3
};
// Where a continued scan differs from the earlier one it is localized on (section 9's change
// report): something appeared (this scan's surface where the earlier scan's laser saw through
// empty space) or vanished (the earlier scan's surface where this scan's laser sees through).
enum class ChangeKind : std::uint8_t { kNone = 0, kAppeared = 1, kVanished = 2 };
enum class CommandState : std::uint32_t {
    kPending = 0,     // sent, the pipeline has not looked at it yet
    kAccepted = 1,    // taken, work not started
    kInProgress = 2,  // long command (export) running; progress in [0, 1]
    kDone = 3,
    kFailed = 4,
    kRejected = 5,  // not allowed now (e.g. export while scanning)
};

// One display point: voxel-downsampled, coloured, in the world frame.
struct DisplayPoint {
    float x_m = 0, y_m = 0, z_m = 0;
    std::uint8_t r = 0, g = 0, b = 0;
    std::uint8_t intensity = 0;  // laser return intensity scaled to 0..255
};

// One pose of the 200 Hz ring. Per-DOF status as the paper's Figure 14 draws it: a DOF (an
// eigenvector direction of eq. (19)) was updated by the visual-inertial odometry (green), else by
// scan matching (blue), else it holds the IMU prediction (orange).
struct PoseRecord {
    std::int64_t t_ns = 0;                          // host CLOCK_MONOTONIC
    double position_m[3] = {0, 0, 0};               // p_world_body
    double orientation_xyzw[4] = {0, 0, 0, 1};      // q_world_body
    float covariance_diag[6] = {0, 0, 0, 0, 0, 0};  // (rx ry rz tx ty tz), rad^2 and m^2
    std::uint8_t vio_dof_mask = 0;   // bit i: DOF i solved by visual-inertial odometry
    std::uint8_t scan_dof_mask = 0;  // bit i: DOF i solved by scan matching
    std::uint8_t source = 0;         // handscan::PoseSource of the estimate
    std::uint8_t reserved[5] = {};
};

// Decimated trajectory for drawing the whole path (the pose ring only holds the last seconds).
struct TrackPoint {
    std::int64_t t_ns = 0;
    float x_m = 0, y_m = 0, z_m = 0;
    float reserved = 0;
};

struct SensorStatus {
    char name[kNameChars] = {};        // "hokuyo", "xsens", "encoder", "tracking-cam", ...
    char last_error[kTextChars] = {};  // empty when healthy; what / where / what to do otherwise
    float rate_hz = 0;                 // measured over the last second
    float expected_rate_hz = 0;        // nominal rate from the configuration
    std::int64_t last_sample_ns = 0;
    std::uint8_t connected = 0;
    std::uint8_t reserved[7] = {};
};

struct ModuleStatus {
    char name[kNameChars] = {};            // "imu", "vio", "scan-match", "colour", ...
    std::uint8_t state = 0;                // ModuleState
    std::uint8_t degenerate_dof_mask = 0;  // directions below the eigenvalue threshold (eq. 19)
    std::uint8_t reserved[2] = {};
    float rate_hz = 0;
};

struct ExportStatus {
    std::uint8_t state = 0;           // ExportState
    std::uint8_t safe_to_remove = 0;  // 1 once the files are verified and the stick is synced
    std::uint8_t reserved[2] = {};
    float progress = 0;  // 0..1
    std::uint64_t bytes_written = 0;
    char target[kTextChars] = {};  // where the export goes (e.g. /media/usb0/scan-0007)
    char message[kTextChars] = {};
};

// One value `handscan calibrate` estimated (in the units it prints: deg, mm, ms).
struct CalibrationValue {
    char name[32] = {};  // "laser roll about shaft x", "encoder zero", "IMU time offset", ...
    char unit[8] = {};
    float start = 0, value = 0, std = 0;  // std: 0 when not estimated
    std::uint8_t written = 0;             // 0: the data did not determine it; kept as it was
    std::uint8_t reserved[3] = {};
};

// The daemon's self-calibration on the last scan (CommandType::kCalibrate): progress, then the
// values with their standard deviations and which were written.
struct CalibrationStatus {
    std::uint8_t state = 0;  // CalibrationState
    std::uint8_t value_count = 0;
    std::uint8_t reserved[2] = {};
    float progress = 0;               // 0..1
    float consistency_before_mm = 0;  // half-revolution consistency, START
    float consistency_after_mm = 0;   // ... with the written calibration
    char message[kTextChars] = {};    // the step running, or the outcome
    char file[kTextChars] = {};       // the calibration.yaml written
    CalibrationValue values[kCalibrationValues] = {};
};

// Everything the status bar shows, replaced as a whole by the writer.
struct StatusBlock {
    std::int64_t t_ns = 0;
    std::uint32_t sensor_count = 0;
    std::uint32_t module_count = 0;
    SensorStatus sensors[kMaxSensors] = {};
    ModuleStatus modules[kMaxModules] = {};
    std::uint8_t scan_state = 0;    // ScanState
    std::uint8_t localization = 0;  // LocalizationState of the current scan
    // 1: an earlier scan on the device can be continued (it left its feature map).
    std::uint8_t can_continue = 0;
    std::uint8_t reserved[5] = {};
    double elapsed_s = 0;           // scanning time of the current scan
    double distance_m = 0;          // path length walked in the current scan
    std::uint64_t point_count = 0;  // full-resolution map points (the display map is sparser)
    std::uint64_t free_storage_bytes = 0;
    std::uint64_t total_storage_bytes = 0;
    float linear_speed_mps = 0;  // for "moving too fast"
    float angular_speed_radps = 0;
    float camera_brightness = 0;  // mean grey level 0..255 of the tracking camera ("too dark")
    float reserved_f = 0;
    ExportStatus export_status = {};
    char message[kTextChars] = {};  // the pipeline's own note to the operator
    CalibrationStatus calibration = {};
};

// One change cell: a cube of ChangeReport::cell_m about its centre, in the map's frame (the
// earlier scan's).
struct ChangeCellRecord {
    float x_m = 0, y_m = 0, z_m = 0;
    std::uint32_t points = 0;  // this scan's points (appeared) or the earlier scan's (vanished)
    std::uint8_t kind = 0;     // ChangeKind
    std::uint8_t reserved[7] = {};
};

// The change report of the current scan, replaced as a whole by the writer after each match to
// the earlier map that the localizer used (0.5 Hz), and emptied by a new scan.
struct ChangeReport {
    std::uint64_t epoch = 0;     // the map epoch it belongs to (older ones are not drawn)
    std::int64_t t_ns = 0;       // when it was published
    float cell_m = 0;            // edge of each cell's cube
    std::uint32_t appeared = 0;  // cells of each kind in the whole report; when they are more
    std::uint32_t vanished = 0;  // than kMaxChangeCells, cells holds the ones with most points
    std::uint32_t count = 0;     // cells[0, count) hold data
    ChangeCellRecord cells[kMaxChangeCells] = {};
};

// A scan on the device that can be continued (the argument "scan=NAME" of kContinueScan).
struct ListedScan {
    char name[48] = {};                // its directory under the journal root
    std::int64_t modified_unix_s = 0;  // its journal's last write (UTC seconds)
    std::uint64_t journal_bytes = 0;   // how big a scan it is
    std::uint8_t current = 0;          // 1: the scan stopped now, its map on the screen
    std::uint8_t reserved[7] = {};
};

// The scans that can be continued, newest first; replaced as a whole when they change.
struct ScanList {
    std::uint32_t count = 0;  // scans[0, count) hold data
    std::uint32_t total = 0;  // on the device (more than kMaxListedScans: the oldest left out)
    ListedScan scans[kMaxListedScans] = {};
};

struct CommandRequest {
    std::uint64_t seq = 0;         // unique, increasing; 0 = slot never used
    std::uint32_t type = 0;        // CommandType
    std::uint32_t sender_pid = 0;  // the UI's process: its unread answers are freed when it dies
    std::int64_t sent_ns = 0;
    char argument[kArgumentChars] = {};  // e.g. the export target directory
};

struct CommandAck {
    std::uint64_t seq = 0;    // the request this answers
    std::uint32_t state = 0;  // CommandState
    float progress = 0;       // 0..1 while kInProgress
    std::int64_t t_ns = 0;
    char message[kTextChars] = {};
};

// ---- The region. Counters are 64-bit words accessed only through std::atomic_ref. ----

struct PoseSlot {
    std::uint64_t seq = 0;  // 2n+1 while pose n is written, 2n+2 once complete
    PoseRecord pose;
};

struct CommandSlot {
    std::uint64_t request_lock = 0;  // seqlock, odd while a UI writes the request (CAS-claimed)
    CommandRequest request;
    std::uint64_t ack_lock = 0;  // seqlock, odd while the pipeline writes the ack
    CommandAck ack;
    std::uint64_t collected_seq = 0;  // the sending UI has read the final answer to this request
};

struct RegionHeader {
    std::uint64_t magic = 0;  // stored last (release) once the region is initialised
    std::uint32_t version = 0;
    std::uint32_t header_bytes = 0;  // sizeof(RegionHeader), a second layout check
    std::uint64_t total_bytes = 0;
    std::uint64_t map_capacity_points = 0;
    std::uint64_t points_offset = 0;  // byte offset of DisplayPoint[map_capacity_points]
    std::uint64_t writer_nonce = 0;  // fresh per writer start: readers reset their caches on change
    std::uint64_t writer_pid = 0;
    std::int64_t writer_started_ns = 0;
    std::uint64_t writer_state = 0;  // WriterState
    std::int64_t heartbeat_ns = 0;   // writer's CLOCK_MONOTONIC at its last publish / tick

    std::uint64_t map_lock = 0;      // 2 * epoch; odd while a new scan resets the map
    std::uint64_t map_points = 0;    // committed display points of this epoch
    std::uint64_t track_points = 0;  // committed track points of this epoch
    std::uint64_t pose_count = 0;    // poses published since the writer started

    std::uint64_t status_lock = 0;
    StatusBlock status;

    std::uint64_t changes_lock = 0;
    ChangeReport changes;

    std::uint64_t scans_lock = 0;
    ScanList scans;

    std::uint64_t next_command_seq = 0;
    std::uint64_t reserved_cmd = 0;
    CommandSlot commands[kCommandSlots];
    PoseSlot poses[kPoseRingCapacity];
    TrackPoint track[kTrackCapacity];
};

static_assert(std::is_trivially_copyable_v<RegionHeader> &&
              std::is_standard_layout_v<RegionHeader>);
static_assert(sizeof(DisplayPoint) == 16);
static_assert(sizeof(CalibrationValue) == 56 && sizeof(CalibrationStatus) % 8 == 0);
static_assert(sizeof(PoseRecord) % 8 == 0 && sizeof(StatusBlock) % 8 == 0);
static_assert(sizeof(ChangeCellRecord) == 24 && sizeof(ChangeReport) % 8 == 0);
static_assert(sizeof(ListedScan) == 72 && sizeof(ScanList) % 8 == 0);
static_assert(sizeof(CommandRequest) % 8 == 0 && sizeof(CommandAck) % 8 == 0);
static_assert(sizeof(TrackPoint) % 8 == 0 && sizeof(RegionHeader) % 8 == 0);

inline constexpr std::size_t regionBytes(std::size_t map_capacity_points) {
    return sizeof(RegionHeader) + map_capacity_points * sizeof(DisplayPoint);
}

const char* toString(CommandType type);
const char* toString(CommandState state);
// Done, failed or rejected: no further answer will come.
bool isFinal(CommandState state);
const char* toString(ScanState state);
const char* toString(LocalizationState state);
const char* toString(ChangeKind kind);

}  // namespace handscan::shm
