#include "handscan/worker/sample_merger.hpp"

namespace handscan::worker {

void SampleMerger::push(sources::Sample sample) {
    streams_[sample.index()].push_back(std::move(sample));
}

std::optional<sources::Sample> SampleMerger::pop(TimeNs horizon) {
    std::deque<sources::Sample>* first = nullptr;
    TimeNs t_first = 0;
    for (auto& stream : streams_) {
        if (stream.empty()) continue;
        const TimeNs t = sources::sampleTime(stream.front());
        if (t > horizon) continue;
        if (first == nullptr || t < t_first) {  // strict: ties go to the earlier kind
            first = &stream;
            t_first = t;
        }
    }
    if (first == nullptr) return std::nullopt;
    sources::Sample s = std::move(first->front());
    first->pop_front();
    return s;
}

std::size_t SampleMerger::size() const {
    std::size_t n = 0;
    for (const auto& stream : streams_) n += stream.size();
    return n;
}

void SampleMerger::clear() {
    for (auto& stream : streams_) stream.clear();
}

}  // namespace handscan::worker
