#include "host/simulate/output.hpp"

#include <unistd.h>

#include <algorithm>
#include <iterator>

namespace eomc::host {

CsvOutput::CsvOutput(const std::string& path, const std::vector<std::string>& columns, std::size_t max_rows)
    : max_rows_(max_rows) {
    if (path.empty()) return;
    out_.emplace(path);  // refuses a target that is not a regular file now, not after a long run
    file_ = out_->stream();
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
    std::string header;
    for (const auto& c : columns) header += (header.empty() ? "" : ",") + c;
    header += '\n';
    std::fwrite(header.data(), 1, header.size(), file_);
}

void CsvOutput::row(double t, const runtime::State<double>& x, const std::vector<double>& invariants,
                    const std::vector<double>& outputs, const std::string* event, bool with_event_column,
                    std::string_view extra) {
    if (!file_) return;
    if (rows_ >= max_rows_) throw RowLimit{t};
    buffer_.clear();
    fmt::format_to(std::back_inserter(buffer_), "{:.17g}", t);
    for (double v : x) fmt::format_to(std::back_inserter(buffer_), ",{:.17g}", v);
    for (double v : invariants) fmt::format_to(std::back_inserter(buffer_), ",{:.17g}", v);
    for (double v : outputs) fmt::format_to(std::back_inserter(buffer_), ",{:.17g}", v);
    buffer_.append(extra.data(), extra.data() + extra.size());
    if (with_event_column) {
        buffer_.push_back(',');
        if (event) buffer_.append(event->data(), event->data() + event->size());
    }
    buffer_.push_back('\n');
    std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
    ++rows_;
}

void CsvOutput::commit() {
    if (!file_) return;
    file_ = nullptr;
    out_->commit();
}

ProgressBar::ProgressBar(bool wanted, double t_end) : enabled_(wanted && ::isatty(STDERR_FILENO)), t_end_(t_end) {}

ProgressBar::~ProgressBar() {
    if (drawn_) std::fputs("\r\033[K", stderr);
}

void ProgressBar::update(double t) {
    // Reading the clock every step would cost more than a small kernel's step.
    if (!enabled_ || (++calls_ & 63u) != 0) return;
    const auto now = Clock::now();
    if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double fraction = std::clamp(t / t_end_, 0.0, 1.0);
    constexpr int width = 30;
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.6g / %.6g", std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), static_cast<int>(fraction * 100), t, t_end_);
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace eomc::host
