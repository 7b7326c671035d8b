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

ProgressBar::ProgressBar(bool wanted, double total, Label label, unsigned check_every, bool always)
    : enabled_(wanted && (always || ::isatty(STDERR_FILENO))), terminal_(::isatty(STDERR_FILENO) != 0),
      always_(always), total_(total), label_(std::move(label)), check_every_(std::max(1u, check_every)) {}

ProgressBar::ProgressBar(bool wanted, double t_end)
    : ProgressBar(wanted, t_end, [](double t, double end) { return fmt::format("t = {:.6g} / {:.6g}", t, end); }, 64) {}

ProgressBar::~ProgressBar() {
    if (drawn_ && terminal_) std::fputs("\r\033[K", stderr);
}

void ProgressBar::update(double done) {
    const bool last = always_ && done >= total_;
    if (!enabled_ || finished_ || (++calls_ % check_every_ != 0 && !last)) return;
    finished_ = last;
    const auto now = Clock::now();
    if (!last && ((!always_ && now - start_ < std::chrono::seconds(1)) || now - last_ < std::chrono::milliseconds(100)))
        return;
    last_ = now;
    const double fraction = total_ > 0 ? std::clamp(done / total_, 0.0, 1.0) : 1.0;
    constexpr int width = 30;
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "%s[%s%s] %3d%%  %s%s", terminal_ ? "\r" : "", std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), static_cast<int>(fraction * 100),
                 label_(done, total_).c_str(), terminal_ ? "" : "\n");
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace eomc::host
