// The command line's progress display (app/progress.hpp): what a terminal sees while the
// renderer builds cone maps on first use.
#include "app/progress.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace {

// Everything written to a temporary file.
std::string contents(std::FILE* f)
{
    std::fflush(f);
    std::rewind(f);
    std::string s;
    for (int c = std::fgetc(f); c != EOF; c = std::fgetc(f)) s += char(c);
    return s;
}

} // namespace

TEST(Progress, TaskProgressDrawsABarPerBuildAndNothingForCacheHits)
{
    std::FILE* out = std::tmpfile();
    ASSERT_NE(out, nullptr);
    {
        pr::TaskProgress p(out, true);
        p("cone map of builtin:noise@64", 1.0); // read from the cache: done at its first report
        EXPECT_EQ(contents(out), "");
        p("relaxed cone map of a.png", 0.25);
        p("relaxed cone map of a.png", 0.5);
        std::string s = contents(out);
        EXPECT_NE(s.find("building relaxed cone map of a.png: [########"), std::string::npos) << s;
        EXPECT_NE(s.find(" 50%"), std::string::npos) << s;
        p("relaxed cone map of a.png", 1.0); // done: the bar is drawn full, then cleared
        s = contents(out);
        EXPECT_NE(s.find("100%"), std::string::npos) << s;
        EXPECT_EQ(s.back(), '\r') << s; // the line is blank again for what follows
        p("cone map of b.png", 0.5); // the next build has a bar of its own
        EXPECT_NE(contents(out).find("building cone map of b.png: "), std::string::npos);
    }
    std::fclose(out);

    // Not a terminal: nothing at all.
    std::FILE* quiet = std::tmpfile();
    ASSERT_NE(quiet, nullptr);
    {
        pr::TaskProgress p(quiet, false);
        p("cone map of a.png", 0.5);
        p("cone map of a.png", 1.0);
    }
    EXPECT_EQ(contents(quiet), "");
    std::fclose(quiet);
}

// Off a terminal, a long task says once how far it is and about how long it has left: a cone map
// of 4096² built for minutes with nothing in the log. Not for a task done at its first report.
TEST(Progress, OffATerminalALongTaskSaysOnceHowFarItIs)
{
    std::FILE* log = std::tmpfile();
    ASSERT_NE(log, nullptr);
    {
        pr::TaskProgress p(log, false, 0.0); // (the notice at once, not after 10 s)
        p("cone map of a.png", 1.0);
        EXPECT_EQ(contents(log), "");
        p("relaxed cone map of b.png", 0.25);
        p("relaxed cone map of b.png", 0.5);
        p("relaxed cone map of b.png", 1.0);
    }
    const std::string s = contents(log);
    EXPECT_EQ(s.rfind("prismrelief: note: building relaxed cone map of b.png: 25% done after ", 0), 0u) << s;
    EXPECT_NE(s.find(" s more\n"), std::string::npos) << s;
    EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 1) << s; // once, on a line of its own
    // Under 1 % after the delay: how far, without an estimate, and the estimate at 1 % (the note
    // waited for 1 %, 77 s into an 8192² relaxed map; forty-fourth session).
    std::FILE* slow = std::tmpfile();
    ASSERT_NE(slow, nullptr);
    {
        pr::ProgressBar bar("conemap", slow, false, 0.0);
        bar(0.002);
        bar(0.004);
        bar(0.02);
        bar(0.5);
    }
    const std::string t = contents(slow);
    EXPECT_EQ(t.rfind("prismrelief: note: conemap: 0.2% done after 0 s (an estimate once 1% is done)\n"
                      "prismrelief: note: conemap: 2% done after ", 0),
              0u)
        << t;
    EXPECT_EQ(std::count(t.begin(), t.end(), '\n'), 2) << t;
    std::fclose(slow);
    std::fclose(log);
    // Before the delay: nothing.
    std::FILE* quiet = std::tmpfile();
    ASSERT_NE(quiet, nullptr);
    {
        pr::ProgressBar bar("conemap", quiet, false, 3600.0);
        bar(0.5);
    }
    EXPECT_EQ(contents(quiet), "");
    std::fclose(quiet);
}

// A bar fits the terminal's width less one column: a line as wide as the terminal wraps, and the
// redraw's "\r" goes back to its last row only (a long map name left a new line on an 80-column
// terminal at every redraw; found by an exploratory session). Long labels lose their middle, cut
// between UTF-8 characters.
TEST(Progress, BarsFitTheTerminalsWidth)
{
    const std::string long_label = "building relaxed cone map of /home/someone/projects/relief/heights/" +
                                   std::string("\xc3\xa9t\xc3\xa9-") + "cobblestones_4096.png";
    for (int columns : {1, 4, 5, 14, 19, 20, 24, 40, 80, 81, 120, 300})
        for (double fraction : {0.0, 0.37, 1.0}) {
            const std::string line = pr::ProgressBar::bar_line(long_label, fraction, columns);
            EXPECT_LE(pr::display_columns(line), std::size_t(columns - 1)) << columns << ": " << line;
            EXPECT_EQ(pr::one_line(line), line) << "not whole UTF-8 characters: " << line;
            if (columns >= 40) EXPECT_NE(line.find("4096.png: ["), std::string::npos) << line; // the name's end
        }
    EXPECT_EQ(pr::ProgressBar::bar_line(long_label, 0.37, 14), " 37%"); // (the bar took 19 columns and wrapped)
    EXPECT_EQ(pr::ProgressBar::bar_line(long_label, 0.37, 4), "");
    // Shortened where it must be only, with the whole 30-wide bar where it fits.
    const std::string wide = pr::ProgressBar::bar_line(long_label, 0.5, 300);
    EXPECT_EQ(wide.rfind(long_label + ": [###############...............]  50%", 0), 0u) << wide;
    const std::string narrow = pr::ProgressBar::bar_line(long_label, 0.5, 80);
    EXPECT_EQ(narrow.rfind("building rel", 0), 0u) << narrow;
    EXPECT_NE(narrow.find("..."), std::string::npos) << narrow;
    // Wide characters take two columns each (a CJK name's bar wrapped: 59 characters in 83
    // columns), and a short label keeps its room for the bar (bench's was 8 wide where 15 fit);
    // found by a review, thirty-fourth session.
    const std::string cjk = "building cone map of \xe5\x9b\xbe\xe5\x83\x8f/" + std::string(20, 'x') +
                            "\xe9\xab\x98\xe5\xba\xa6\xe5\x9b\xbe\xe9\xab\x98\xe5\xba\xa6\xe5\x9b\xbe.png";
    EXPECT_EQ(pr::display_columns("\xe9\xab\x98\xe5\xba\xa6"), 4u);
    EXPECT_EQ(pr::display_columns("e\xcc\x81"), 1u); // (a combining accent)
    EXPECT_EQ(pr::display_columns("\xf0\x9f\x9a\x80\xe2\xad\x90"), 4u); // U+1F680, U+2B50: wide (a review)
    EXPECT_EQ(pr::shortened_to_columns("abcdefgh", 2), "..");
    EXPECT_EQ(pr::shortened_to_columns("abcdefghij\xe9\xab\x98\xcc\x81", 4), "...");
    for (int columns = 20; columns <= 90; ++columns) {
        const std::string line = pr::ProgressBar::bar_line(cjk, 0.5, columns);
        EXPECT_LE(pr::display_columns(line), std::size_t(columns - 1)) << columns << ": " << line;
        EXPECT_EQ(pr::one_line(line), line) << "not whole UTF-8 characters: " << line;
    }
    EXPECT_EQ(pr::ProgressBar::bar_line("bench", 1.0 / 3.0, 30), "bench: [#####..........]  33%");

    // Drawn at that width, and cleared over all of it.
    std::FILE* out = std::tmpfile();
    ASSERT_NE(out, nullptr);
    {
        pr::ProgressBar bar(long_label, out, true, 10.0, 60);
        bar(0.5);
        EXPECT_EQ(contents(out), "\r" + pr::ProgressBar::bar_line(long_label, 0.5, 60));
    }
    EXPECT_EQ(contents(out), "\r" + pr::ProgressBar::bar_line(long_label, 0.5, 60) + "\r" + std::string(59, ' ') + "\r");
    std::fclose(out);
}

// A warning while a bar is shown goes on a line of its own above it, and the bar is drawn again
// under it (a cache warning ran on from "[###...###] 100%"; found by an exploratory session).
TEST(Progress, AWarningGoesAboveTheBar)
{
    testing::internal::CaptureStderr();
    {
        pr::ProgressBar bar("conemap", stderr, true, 10.0, 80);
        bar(1.0);
        pr::warn("test_progress: a warning while a bar is shown");
    }
    const std::string s = testing::internal::GetCapturedStderr();
    const std::string line = pr::ProgressBar::bar_line("conemap", 1.0, 80);
    const std::string blank = "\r" + std::string(line.size(), ' ') + "\r";
    EXPECT_EQ(s, "\r" + line + blank + "prismrelief: warning: test_progress: a warning while a bar is shown\n" + line + blank);
}
