// The one line an error or warning is printed as (core/error: one_line).
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

TEST(OneLine, ControlCharactersAreWrittenOut)
{
    EXPECT_EQ(pr::one_line("a\nb\tc\x01"), "a\\nb\\tc\\x01");
}

// UTF-8 is kept; bytes that are not UTF-8 are written out as control characters are (a scene in
// Latin-1 or UTF-16 echoed its raw bytes in the JSON parser's message).
TEST(OneLine, BytesThatAreNotUtf8AreWrittenOut)
{
    EXPECT_EQ(pr::one_line("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"), "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80");
    EXPECT_EQ(pr::one_line("caf\xE9!"), "caf\\xe9!");                  // Latin-1 é
    EXPECT_EQ(pr::one_line("\xFF\xFE{"), "\\xff\\xfe{");                // a UTF-16 byte-order mark
    EXPECT_EQ(pr::one_line("\xC3"), "\\xc3");                           // cut short
    EXPECT_EQ(pr::one_line("\xC0\xAF"), "\\xc0\\xaf");                 // overlong '/'
    EXPECT_EQ(pr::one_line("\xED\xA0\x80"), "\\xed\\xa0\\x80");       // a surrogate
    EXPECT_EQ(pr::one_line("a\x7f"), "a\\x7f");
    // UTF-8 that breaks the line or steers the terminal: C1 controls (NEL, CSI), the line
    // separator, a right-to-left override.
    EXPECT_EQ(pr::one_line("a\xC2\x85" "b\xC2\x9B"), "a\\xc2\\x85b\\xc2\\x9b");
    EXPECT_EQ(pr::one_line("\xE2\x80\xA8|\xE2\x80\xAE"), "\\xe2\\x80\\xa8|\\xe2\\x80\\xae");
    EXPECT_EQ(pr::one_line("\xC2\xA0\xE2\x80\x94"), "\xC2\xA0\xE2\x80\x94"); // no-break space, em dash: as they are
}

// A scene naming its mesh by a 5 MB path printed a 5 MB line (found by an exploratory session,
// sixteenth session): the start and the end (the problem) stay, the middle is left out and said
// so, cut between UTF-8 characters.
TEST(OneLine, AVeryLongLineKeepsItsStartAndEnd)
{
    std::string name = "objects[0].mesh: ";
    for (int i = 0; i < 100000; ++i) name += "\xC3\xA9"; // é, two bytes each
    const std::string line = pr::one_line(name + ": does not exist");
    EXPECT_LE(line.size(), pr::kLongestLine + 64);
    EXPECT_EQ(line.rfind("objects[0].mesh: \xC3\xA9", 0), 0u);
    EXPECT_EQ(line.substr(line.size() - 16), ": does not exist");
    EXPECT_NE(line.find(" bytes left out ...] "), std::string::npos);
    const std::size_t cut = line.find(" [... ");
    ASSERT_NE(cut, std::string::npos);
    EXPECT_EQ(static_cast<unsigned char>(line[cut - 1]), 0xA9u); // a whole character before the cut
    const std::size_t after = line.find("...] ") + 5;
    EXPECT_EQ(static_cast<unsigned char>(line[after]), 0xC3u); // and after it
    EXPECT_EQ(pr::one_line(std::string(pr::kLongestLine, 'x')), std::string(pr::kLongestLine, 'x'));
}

// Bytes that are not UTF-8 (a file name of 6000 bytes 0x80): the cut looked for a character's
// start through all of them, cut nothing and said "0 bytes left out" (found by a review).
TEST(OneLine, ALongLineOfBytesThatAreNotUtf8IsCutToo)
{
    const std::string line = pr::one_line(std::string(6000, '\x80') + ": does not exist");
    EXPECT_LE(line.size(), pr::kLongestLine + 64);
    EXPECT_EQ(line.find(" [... 0 bytes"), std::string::npos);
    EXPECT_EQ(line.substr(line.size() - 16), ": does not exist");
}

// The viewer's panel log shows the warnings stderr shows (observe_warnings): those said before it
// looks, in order, then each one as it is said, once, without the "prismrelief: warning: " prefix.
TEST(Warnings, AnObserverHearsThoseSaidBeforeAndAfter)
{
    testing::internal::CaptureStderr();
    pr::warn("observer test: before\nthe observer");
    std::vector<std::string> heard;
    pr::observe_warnings([&heard](const std::string& message) { heard.push_back(message); });
    pr::warn("observer test: after it");
    pr::warn("observer test: after it"); // (said once)
    pr::observe_warnings({});
    pr::warn("observer test: once it stopped");
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("prismrelief: warning: observer test: once it stopped\n"), std::string::npos) << err;
    std::vector<std::string> ours; // (other tests' warnings may come before)
    for (const std::string& m : heard)
        if (m.rfind("observer test:", 0) == 0) ours.push_back(m);
    EXPECT_EQ(ours, (std::vector<std::string>{"observer test: before\\nthe observer", "observer test: after it"}));
}

// A thread's held warnings (ThreadWarningHold): said on release, dropped and forgotten where it
// ends unreleased, and another thread's said at once meanwhile. warn_each_time says a message
// every time (the viewer's refusals), warn once.
TEST(Warnings, AThreadsHoldKeepsItsOwnAndEachTimeRepeats)
{
    testing::internal::CaptureStderr();
    {
        pr::ThreadWarningHold held;
        pr::warn("hold test: dropped");
        std::thread([] { pr::warn("hold test: another thread's"); }).join();
    }
    const std::string dropped = testing::internal::GetCapturedStderr();
    EXPECT_EQ(dropped.find("hold test: dropped"), std::string::npos) << dropped;
    EXPECT_NE(dropped.find("prismrelief: warning: hold test: another thread's\n"), std::string::npos) << dropped;
    testing::internal::CaptureStderr();
    {
        pr::ThreadWarningHold held;
        pr::warn("hold test: dropped"); // (forgotten when dropped: said now)
        EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
        testing::internal::CaptureStderr();
        held.release();
    }
    pr::warn_each_time("hold test: each time");
    pr::warn_each_time("hold test: each time");
    pr::warn("hold test: each time"); // (said already: once is enough for warn)
    const std::string said = testing::internal::GetCapturedStderr();
    EXPECT_EQ(said, "prismrelief: warning: hold test: dropped\n"
                    "prismrelief: warning: hold test: each time\n"
                    "prismrelief: warning: hold test: each time\n");
}
