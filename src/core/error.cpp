#include "core/error.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <locale.h>
#include <unistd.h>
#include <wchar.h>

namespace pr {

namespace {

struct Warnings {
    std::mutex mutex;
    std::set<std::string> said;
    bool holding = false;
    std::vector<std::string> held; // lines, in order
    std::vector<std::string> printed; // messages, in order (for an observer that comes later)
    std::function<void(const std::string&)> observer;
    std::FILE* status_out = nullptr; // status_line()'s, while one is shown
    std::string status;
};

Warnings& warnings()
{
    static Warnings w;
    return w;
}

// The status line shown, for a signal handler: its descriptor (-1: none) and its columns. (A
// SIGINT during a cone map's build left the bar on the terminal, the shell's prompt or the next
// output run on from "… 52%"; found by an exploratory session, thirty-second.)
std::atomic<int> g_status_fd{-1};
std::atomic<int> g_status_columns{0};
static_assert(std::atomic<int>::is_always_lock_free, "a signal handler reads them");

constexpr std::string_view kWarningPrefix = "prismrelief: warning: ";

// Prints a warning's line on stderr, around the status line if one is shown there, and hands its
// message to the observer (w.mutex held).
void print_warning(Warnings& w, const std::string& line)
{
    std::string message = line.substr(kWarningPrefix.size(), line.size() - kWarningPrefix.size() - 1);
    if (w.observer) w.observer(message);
    w.printed.push_back(std::move(message));
    const bool around = w.status_out == stderr && !w.status.empty();
    if (around) std::fprintf(stderr, "\r%*s\r", int(display_columns(w.status)), "");
    std::fputs(line.c_str(), stderr);
    if (around) std::fprintf(stderr, "%s", w.status.c_str());
    std::fflush(stderr);
}

} // namespace

void status_line(std::FILE* out, const std::string& line)
{
    Warnings& w = warnings();
    std::lock_guard lock(w.mutex);
    const std::size_t shown = w.status_out == out ? display_columns(w.status) : 0;
    // For a signal that comes while the line is written: what it may find on the terminal (the
    // wider of the two lines), before the write.
    g_status_columns = int(std::max(shown, display_columns(line)));
    g_status_fd = ::fileno(out);
    if (line.empty()) {
        if (shown > 0) std::fprintf(out, "\r%*s\r", int(shown), "");
    } else {
        // Over the line shown, and blanks where it was longer.
        const std::size_t length = display_columns(line);
        std::fprintf(out, "\r%s%*s", line.c_str(), int(shown > length ? shown - length : 0), "");
    }
    std::fflush(out);
    w.status_out = line.empty() ? nullptr : out;
    w.status = line;
    g_status_columns = int(display_columns(line));
    if (line.empty()) g_status_fd = -1;
}

void clear_status_line_in_signal_handler() noexcept
{
    const int fd = g_status_fd.exchange(-1);
    if (fd < 0) return;
    static const char blanks[64] = {'\r', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ',
                                    ' ',  ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ',
                                    ' ',  ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ',
                                    ' ',  ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' ', ' '};
    // "\r", the line's columns in blanks, "\r" (what is unwritten stays unwritten: the process dies).
    if (::write(fd, blanks, 1) != 1) return;
    for (int left = g_status_columns.load(); left > 0;) {
        const int n = left < 63 ? left : 63;
        if (::write(fd, blanks + 1, std::size_t(n)) != n) return;
        left -= n;
    }
    [[maybe_unused]] const ssize_t ignored = ::write(fd, blanks, 1);
}

namespace {

// The character starting at byte `i` of `text` (UTF-8; a stray or cut byte stands for itself) and
// its length in bytes.
std::pair<char32_t, std::size_t> character_at(std::string_view text, std::size_t i)
{
    const auto b = static_cast<unsigned char>(text[i]);
    const std::size_t n = b < 0x80u ? 1 : (b >> 5) == 0x6u ? 2 : (b >> 4) == 0xEu ? 3 : (b >> 3) == 0x1Eu ? 4 : 1;
    if (n == 1 || i + n > text.size()) return {b, 1};
    char32_t c = b & (0x7Fu >> n);
    for (std::size_t k = 1; k < n; ++k) {
        const auto next = static_cast<unsigned char>(text[i + k]);
        if ((next & 0xC0u) != 0x80u) return {b, 1};
        c = (c << 6) | (next & 0x3Fu);
    }
    return {c, n};
}

// The columns a terminal gives character `c`: the C library's wcwidth under the C.UTF-8 locale
// (glibc's tables, which terminals follow: two for wide and full-width characters and emoji, none
// for combining marks), one for what it calls unprintable. Where that locale is missing, a table
// of the main blocks: two for CJK, Hangul, full-width forms and emoji, none for combining marks
// and zero-width spaces. (The table alone, in the first version, counted 8,556 wide characters
// one column, 🚀 among them; found by a review.)
std::size_t character_columns(char32_t c)
{
    static const locale_t utf8 = newlocale(LC_CTYPE_MASK, "C.UTF-8", locale_t(0));
    if (utf8 && c <= 0x10FFFF) {
        const locale_t before = uselocale(utf8);
        const int w = wcwidth(static_cast<wchar_t>(c));
        uselocale(before);
        return w < 0 ? 1 : std::size_t(w);
    }
    static constexpr std::pair<char32_t, char32_t> wide[] = {
        {0x1100, 0x115F},   {0x2E80, 0x303E},   {0x3041, 0x33FF},   {0x3400, 0x4DBF}, {0x4E00, 0x9FFF},
        {0xA000, 0xA4CF},   {0xAC00, 0xD7A3},   {0xF900, 0xFAFF},   {0xFE30, 0xFE4F}, {0xFF00, 0xFF60},
        {0xFFE0, 0xFFE6},   {0x1F300, 0x1F64F}, {0x1F900, 0x1F9FF}, {0x20000, 0x3FFFD}};
    static constexpr std::pair<char32_t, char32_t> none[] = {{0x0300, 0x036F}, {0x200B, 0x200F}, {0xFE00, 0xFE0F}};
    for (const auto& [lo, hi] : wide)
        if (c >= lo && c <= hi) return 2;
    for (const auto& [lo, hi] : none)
        if (c >= lo && c <= hi) return 0;
    return 1;
}

} // namespace

std::size_t display_columns(std::string_view line)
{
    std::size_t n = 0;
    for (std::size_t i = 0; i < line.size();) {
        const auto [c, bytes] = character_at(line, i);
        n += character_columns(c);
        i += bytes;
    }
    return n;
}

std::string shortened_to_columns(const std::string& text, std::size_t columns)
{
    if (display_columns(text) <= columns) return text;
    if (columns < 3) return std::string(columns, '.'); // (no room for "..." and anything)
    const std::size_t keep = columns - 3, head = keep / 4, tail = keep - head;
    // Whole characters from the start while they fit in `head` columns, and from the end in `tail`.
    std::size_t head_end = 0;
    for (std::size_t used = 0; head_end < text.size();) {
        const auto [c, bytes] = character_at(text, head_end);
        const std::size_t w = character_columns(c);
        if (used + w > head) break;
        used += w;
        head_end += bytes;
    }
    std::vector<std::size_t> starts; // where each character starts
    for (std::size_t i = 0; i < text.size(); i += character_at(text, i).second) starts.push_back(i);
    std::size_t tail_start = text.size();
    for (std::size_t k = starts.size(), used = 0; k-- > 0 && starts[k] >= head_end;) {
        const std::size_t w = character_columns(character_at(text, starts[k]).first);
        if (used + w > tail) break;
        used += w;
        tail_start = starts[k];
    }
    // (Not a combining mark whose base did not fit: it would sit on the last dot.)
    while (tail_start < text.size() && character_columns(character_at(text, tail_start).first) == 0)
        tail_start += character_at(text, tail_start).second;
    return text.substr(0, head_end) + "..." + text.substr(tail_start);
}

namespace {

// The messages this thread's innermost ThreadWarningHold holds (null: none).
thread_local std::vector<std::string>* t_held = nullptr;

// Hands `message` to this thread's ThreadWarningHold, or prints it as a warning, or holds it
// (hold_warnings); w.mutex held.
void say_warning(Warnings& w, const std::string& message)
{
    if (t_held) {
        t_held->push_back(message);
        return;
    }
    const std::string line = std::string(kWarningPrefix) + one_line(message) + "\n";
    if (w.holding) w.held.push_back(line);
    else print_warning(w, line);
}

} // namespace

void warn(const std::string& message)
{
    Warnings& w = warnings();
    std::lock_guard lock(w.mutex);
    if (w.said.insert(message).second) say_warning(w, message);
}

void warn_each_time(const std::string& message)
{
    Warnings& w = warnings();
    std::lock_guard lock(w.mutex);
    w.said.insert(message);
    say_warning(w, message);
}

ThreadWarningHold::ThreadWarningHold() : outer_(t_held)
{
    t_held = &messages_;
}

ThreadWarningHold::~ThreadWarningHold()
{
    if (!released_) {
        // Dropped, and forgotten: said again should they come again.
        Warnings& w = warnings();
        std::lock_guard lock(w.mutex);
        for (const std::string& message : messages_) w.said.erase(message);
    }
    t_held = outer_;
}

void ThreadWarningHold::release()
{
    if (released_) return;
    released_ = true;
    t_held = outer_; // (so that they go to an outer hold, if any)
    Warnings& w = warnings();
    std::lock_guard lock(w.mutex);
    for (const std::string& message : messages_) say_warning(w, message);
}

void observe_warnings(std::function<void(const std::string&)> observer)
{
    Warnings& w = warnings();
    std::lock_guard lock(w.mutex);
    w.observer = std::move(observer);
    if (w.observer)
        for (const std::string& message : w.printed) w.observer(message);
}

void hold_warnings()
{
    Warnings& w = warnings();
    std::lock_guard lock(w.mutex);
    w.holding = true;
}

namespace {

// Stops holding warnings, printing those held or not.
void stop_holding(bool print)
{
    Warnings& w = warnings();
    std::lock_guard lock(w.mutex);
    if (print)
        for (const std::string& line : w.held) print_warning(w, line);
    w.held.clear();
    w.holding = false;
}

} // namespace

void release_warnings()
{
    stop_holding(true);
}

void drop_warnings()
{
    stop_holding(false);
}

namespace {

// The length of the well-formed UTF-8 character at the start of `s` (RFC 3629: no overlong forms,
// no surrogates, nothing past U+10FFFF), or 0 if it does not start with one.
std::size_t utf8_length(std::string_view s)
{
    const auto at = [&s](std::size_t i) { return i < s.size() ? static_cast<unsigned char>(s[i]) : 0u; };
    const unsigned lead = at(0);
    std::size_t n = 0;
    unsigned lo = 0x80, hi = 0xBF; // the second byte's range
    if (lead >= 0xC2 && lead <= 0xDF) n = 2;
    else if (lead >= 0xE0 && lead <= 0xEF) n = 3, lo = lead == 0xE0 ? 0xA0 : 0x80, hi = lead == 0xED ? 0x9F : 0xBF;
    else if (lead >= 0xF0 && lead <= 0xF4) n = 4, lo = lead == 0xF0 ? 0x90 : 0x80, hi = lead == 0xF4 ? 0x8F : 0xBF;
    else return 0;
    if (at(1) < lo || at(1) > hi) return 0;
    for (std::size_t i = 2; i < n; ++i)
        if (at(i) < 0x80 || at(i) > 0xBF) return 0;
    return n;
}

// Characters that break a line or steer a terminal's output although they are UTF-8: the C1
// controls (U+0085 is a line break, U+009B starts an escape sequence on some terminals), the line
// and paragraph separators and the bidirectional overrides and isolates, which reorder the text
// shown (found by a review). Written out as their bytes.
bool steers_output(std::string_view s, std::size_t n)
{
    std::uint32_t cp = static_cast<unsigned char>(s[0]) & (n == 2 ? 0x1Fu : n == 3 ? 0x0Fu : 0x07u);
    for (std::size_t i = 1; i < n; ++i) cp = (cp << 6) | (static_cast<unsigned char>(s[i]) & 0x3Fu);
    return (cp >= 0x80 && cp <= 0x9F) || cp == 0x2028 || cp == 0x2029 || (cp >= 0x202A && cp <= 0x202E) ||
           (cp >= 0x2066 && cp <= 0x2069);
}

} // namespace

std::string one_line(std::string_view text)
{
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        const auto u = static_cast<unsigned char>(c);
        // UTF-8 as it is (file names in other scripts); a byte that is not part of a character
        // written out, as control characters are (a scene in UTF-16 or Latin-1 echoed its raw
        // bytes in the JSON parser's message; found by an exploratory session).
        if (u >= 0x80) {
            if (const std::size_t n = utf8_length(text.substr(i)); n > 0 && !steers_output(text.substr(i), n)) {
                out.append(text.substr(i, n));
                i += n - 1;
                continue;
            }
        }
        if (u >= 0x20 && u < 0x7f) {
            out.push_back(c);
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else {
            static constexpr char kHex[] = "0123456789abcdef";
            out += "\\x";
            out.push_back(kHex[u >> 4]);
            out.push_back(kHex[u & 15]);
        }
    }
    // A line of megabytes (a scene naming a mesh by a 5 MB path: stderr took 5 MB, 10 for a
    // built-in name said twice) keeps its start and its end, where the problem is said, cut at
    // UTF-8 character boundaries.
    if (out.size() > kLongestLine) {
        // (A UTF-8 character continues for at most 3 bytes; in bytes that are not UTF-8, cut anywhere.)
        const auto boundary = [&out](std::size_t i) {
            for (int k = 0; k < 3 && i > 0 && (static_cast<unsigned char>(out[i]) & 0xC0) == 0x80; ++k) --i;
            return i;
        };
        const std::size_t head = boundary(kLongestLine / 2), tail = boundary(out.size() - kLongestLine / 2);
        out = out.substr(0, head) + " [... " + std::to_string(tail - head) + " bytes left out ...] " + out.substr(tail);
    }
    return out;
}

} // namespace pr
