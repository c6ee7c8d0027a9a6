#pragma once
// The bytes a forward run travels as between ranks: a SimulationRequest {ModelPoint, seed}
// to a worker, a SimulationOutcome {ok, curves or error message} back. Curves are counts
// followed by the raw doubles, so a worker's result reaches rank 0 bit for bit (the report
// is then the same as a threaded run's). Native byte order and IEEE doubles: the ranks of
// one job run the same build on one architecture (README, "Scale-out over MPI").
//
// decode_* throw std::runtime_error naming what was cut short or out of range.
#include <cstdint>
#include <string>
#include <string_view>

#include "engine/diagnose/simulation_batch.hpp"

namespace triax::scaleout {

// Appends plain values to a byte string.
class WireWriter {
public:
    void u64(std::uint64_t v) { raw(&v, sizeof v); }
    void f64(double v) { raw(&v, sizeof v); }
    void bytes(std::string_view s) {
        u64(s.size());
        out_.append(s.data(), s.size());
    }
    void doubles(const std::vector<double>& v) {
        u64(v.size());
        if (!v.empty()) raw(v.data(), v.size() * sizeof(double));
    }
    std::string take() { return std::move(out_); }

private:
    void raw(const void* p, std::size_t n) { out_.append(static_cast<const char*>(p), n); }
    std::string out_;
};

// Reads them back in the same order; every read checks the remaining length.
class WireReader {
public:
    explicit WireReader(std::string_view in) : in_(in) {}
    std::uint64_t u64(const char* what);
    double f64(const char* what);
    std::string bytes(const char* what);
    std::vector<double> doubles(const char* what);
    bool done() const { return at_ == in_.size(); }

private:
    void raw(void* p, std::size_t n, const char* what);
    std::string_view in_;
    std::size_t at_ = 0;
};

std::string encode_request(const diagnose::SimulationRequest& r);
diagnose::SimulationRequest decode_request(std::string_view bytes);

void write_dataset(WireWriter& w, const diagnose::LabDataset& d);
diagnose::LabDataset read_dataset(WireReader& r);

std::string encode_outcome(const diagnose::SimulationOutcome& o);
diagnose::SimulationOutcome decode_outcome(std::string_view bytes);

}  // namespace triax::scaleout
