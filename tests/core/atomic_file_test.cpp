#include <gtest/gtest.h>

#include <fstream>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {

std::size_t entries(const std::filesystem::path& dir) {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir), {}));
}

TEST(AtomicFile, NothingVisibleUntilCommit) {
    const auto dir = test::temp_dir();
    {
        AtomicFile f(dir / "out.txt");
        f.stream() << "hello";
        EXPECT_FALSE(std::filesystem::exists(dir / "out.txt"));
        f.commit();
    }
    std::ifstream in(dir / "out.txt");
    std::string s;
    in >> s;
    EXPECT_EQ(s, "hello");
    EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, AbandonedWriteLeavesNoFile) {
    const auto dir = test::temp_dir();
    write_file_atomically(dir / "keep.txt", "old");
    try {
        AtomicFile f(dir / "keep.txt");
        f.stream() << "half";
        throw std::runtime_error("interrupted");
    } catch (const std::runtime_error&) {
    }
    std::ifstream in(dir / "keep.txt");
    std::string s;
    in >> s;
    EXPECT_EQ(s, "old");
    EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, MissingDirectoryIsInputError) {
    const auto dir = test::temp_dir();
    EXPECT_THROW(AtomicFile(dir / "no" / "such" / "x.txt"), InputError);
    EXPECT_THROW(check_writable(dir), InputError);
    EXPECT_NO_THROW(check_writable(dir / "fine.txt"));
}

}  // namespace
}  // namespace foldcast

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include "foldcast/core/interrupt_cleanup.hpp"

namespace foldcast {
namespace {

std::string read_all(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::string s;
    in >> s;
    return s;
}

TEST(OutputTransaction, AllFilesOrNone) {
    const auto dir = test::temp_dir();
    write_file_atomically(dir / "a.txt", "old-a");
    write_file_atomically(dir / "b.txt", "old-b");
    {
        OutputTransaction t;
        t.stage(dir / "a.txt") << "new-a";
        t.stage(dir / "b.txt") << "new-b";
        EXPECT_EQ(entries(dir), 4u);  // two targets, two temporaries
    }                                 // abandoned
    EXPECT_EQ(read_all(dir / "a.txt"), "old-a");
    EXPECT_EQ(read_all(dir / "b.txt"), "old-b");
    EXPECT_EQ(entries(dir), 2u);
    OutputTransaction t;
    t.stage(dir / "a.txt") << "new-a";
    t.stage(dir / "b.txt") << "new-b";
    EXPECT_THROW(t.stage(dir / "a.txt"), InputError);
    t.commit();
    EXPECT_EQ(read_all(dir / "a.txt"), "new-a");
    EXPECT_EQ(read_all(dir / "b.txt"), "new-b");
    EXPECT_EQ(entries(dir), 2u);
}

// A file the new set replaces without a new version (a longer run's extra frame) goes with
// the commit, and only with it: an abandoned transaction leaves it.
TEST(OutputTransaction, RemovesOnCommitOnly) {
    const auto dir = test::temp_dir();
    write_file_atomically(dir / "frame_0.png", "old-0");
    write_file_atomically(dir / "frame_1.png", "old-1");
    {
        OutputTransaction t;
        t.stage(dir / "frame_0.png") << "new-0";
        t.remove_on_commit(dir / "frame_1.png");
    }  // abandoned
    EXPECT_EQ(read_all(dir / "frame_1.png"), "old-1");
    OutputTransaction t;
    t.stage(dir / "frame_0.png") << "new-0";
    t.remove_on_commit(dir / "frame_1.png");
    t.commit();
    EXPECT_EQ(read_all(dir / "frame_0.png"), "new-0");
    EXPECT_FALSE(std::filesystem::exists(dir / "frame_1.png"));
    EXPECT_EQ(entries(dir), 1u);
}

// Runs `body` in a child process and returns its wait status.
template <typename Body>
int in_child(Body body) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        body();
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
}

TEST(InterruptCleanup, SignalRemovesLiveTemporariesAndStillKills) {
    const auto dir = test::temp_dir();
    for (int sig : {SIGINT, SIGTERM}) {
        const int status = in_child([&] {
            OutputTransaction t;
            t.stage(dir / "out.txt") << "half";
            t.stage_file(dir / "video.mp4");
            std::ofstream(t.staged(dir / "video.mp4")) << "x";
            ::raise(sig);
        });
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
        EXPECT_EQ(entries(dir), 0u) << "a temporary survived signal " << sig;
    }
}

// A signal during a commit waits for the last rename: the process dies with every new file in place.
TEST(InterruptCleanup, DeferralHoldsTheSignalUntilItEnds) {
    const auto dir = test::temp_dir();
    const int status = in_child([&] {
        const InterruptDeferral hold;
        ::raise(SIGTERM);
        std::ofstream(dir / "after-signal.txt") << "written";
    });
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
    EXPECT_EQ(read_all(dir / "after-signal.txt"), "written");
}

// Files that belong together (a PC2 and its OBJ): when the second rename fails (here its
// target became a directory; `chattr +i` on a real one), the first is undone, so the old pair
// stays as it was.  The first rename used to stay, leaving a new PC2 beside the old OBJ.
TEST(AtomicFile, AFailedSecondRenamePutsTheFirstBack) {
    const auto dir = test::temp_dir();
    write_file_atomically(dir / "x.pc2", "old pc2");
    {
        OutputTransaction pair;
        pair.stage(dir / "x.pc2") << "new pc2";
        pair.stage(dir / "x.obj") << "new obj";
        std::filesystem::create_directory(dir / "x.obj");  // the second target can no longer be replaced
        EXPECT_THROW(pair.commit(), std::runtime_error);
    }
    std::ifstream in(dir / "x.pc2");
    std::string s;
    std::getline(in, s);
    EXPECT_EQ(s, "old pc2");
    EXPECT_EQ(entries(dir), 2u) << "a temporary or backup was left behind";  // x.pc2 and the directory
}

}  // namespace
}  // namespace foldcast
