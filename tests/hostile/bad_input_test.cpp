// Issue #17 items 4-7 and the bad-value part of its battery: every hostile value or file
// below must end foldcast with our exit status and our own first line naming what is wrong
// (no OpenCV assertion, no libpng/libjpeg line, no default scene rendered, no silent wrap).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "crc32.hpp"
#include "run_command.hpp"
#include "spawn.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

std::string bytes_of(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class BadInput : public ::testing::Test {
protected:
    void SetUp() override { dir_ = test::temp_dir(); }

    test::Outcome run(std::vector<std::string> args) {
        args.insert(args.begin(), test::foldcast_under_test());
        return test::run_child(args, dir_ / "stderr.txt", {30, 4ull << 30});
    }
    // Exit `status` and a first stderr line of ours containing `needle`, no library noise.
    void expect_refused(const std::vector<std::string>& args, int status, const std::string& needle) {
        std::string line;
        for (const auto& a : args) line += " " + a;
        const test::Outcome o = run(args);
        EXPECT_TRUE(o.exited && o.exit_code == status)
            << line << ": exit " << o.exit_code << " signal " << o.signal << ": " << o.err;
        const std::string first = o.err.substr(0, o.err.find('\n'));
        EXPECT_EQ(first.rfind("foldcast", 0), 0u) << line << ": " << o.err;
        EXPECT_NE(first.find(needle), std::string::npos)
            << line << ": the first line does not name '" << needle << "': " << o.err;
        expect_only_our_lines(o, line);
    }
    // Every stderr line is ours: library text (libpng, libjpeg, OpenCV's assertions) only
    // inside one of them.
    static void expect_only_our_lines(const test::Outcome& o, const std::string& line) {
        std::size_t at = 0;
        while (at < o.err.size()) {
            const std::size_t end = o.err.find('\n', at);
            const std::string text = o.err.substr(at, end == std::string::npos ? std::string::npos : end - at);
            EXPECT_TRUE(text.rfind("foldcast", 0) == 0 || text.rfind("Run with --help", 0) == 0)
                << line << ": a line that is not ours: " << text;
            if (end == std::string::npos) break;
            at = end + 1;
        }
    }
    fs::path write(const std::string& name, const std::string& bytes) {
        std::ofstream(dir_ / name, std::ios::binary) << bytes;
        return dir_ / name;
    }
    // A width x height single-channel float PFM (OpenCV reads it; little-endian: scale < 0).
    fs::path pfm(const std::string& name, int width, int height, float value) {
        std::string bytes = "Pf\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
        for (int i = 0; i < width * height; ++i) bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
        return write(name, bytes);
    }

    fs::path dir_;
};

// Item 4: a gate fails closed.
TEST_F(BadInput, DiffFailsOnNanAndRefusesNonsenseThresholds) {
    const fs::path nan = pfm("nan.pfm", 8, 8, std::numeric_limits<float>::quiet_NaN());
    const fs::path zero = pfm("zero.pfm", 8, 8, 0.0f);
    const fs::path one = pfm("one.pfm", 8, 8, 1.0f);
    const test::Outcome o = run({"diff", nan.string(), zero.string()});
    EXPECT_EQ(o.exit_code, 2) << "all-NaN against all-zero must be FAILURE: " << o.err;
    EXPECT_EQ(run({"diff", zero.string(), nan.string(), "--failpercent", "100", "--allowfailures", "1000"}).exit_code,
              2);
    EXPECT_EQ(run({"diff", zero.string(), zero.string()}).exit_code, 0);
    for (const char* value : {"nan", "-1"})
        expect_refused({"diff", zero.string(), one.string(), "--fail", value}, 2, "--fail");
    expect_refused({"diff", zero.string(), one.string(), "--failpercent", "nan"}, 2, "--failpercent");
    expect_refused({"diff", zero.string(), one.string(), "--hardfail", "nan"}, 2, "--hardfail");
    expect_refused({"diff", zero.string(), one.string(), "--warn", "nan"}, 2, "--warn");
    for (const char* value : {"99999999999999999999", "-1", "1.5"})
        expect_refused({"diff", zero.string(), one.string(), "--allowfailures", value}, 2, "--allowfailures");
}

// Item 7: an output equal to an input is refused before anything is written.
TEST_F(BadInput, DiffRefusesToOverwriteAnInput) {
    const fs::path a = pfm("a.pfm", 8, 8, 0.25f);
    const fs::path b = pfm("b.pfm", 8, 8, 0.5f);
    fs::copy_file(test::test_data("photos/two_point_shirt_s3_half.jpg"), dir_ / "photo.jpg");
    const std::string before = bytes_of(a);
    expect_refused({"diff", a.string(), b.string(), "-o", a.string()}, 4, a.string());
    EXPECT_EQ(bytes_of(a), before);
    expect_refused({"diff", a.string(), b.string(), "-o", (dir_ / "." / "b.pfm").string()}, 4, "b.pfm");
    const std::string photo = (dir_ / "photo.jpg").string(), photo_bytes = bytes_of(photo);
    expect_refused({"folds", photo, "-o", photo, "--supports", "197.5,50,357.5,48.5"}, 2, "-o");
    expect_refused({"overlay", photo, "-o", photo, "--supports", "197.5,50,357.5,48.5", "--scale-px-per-m", "400"}, 2,
                   "-o");
    EXPECT_EQ(bytes_of(photo), photo_bytes);
}

// A JPEG whose SOF0 claims 65535 x 65535 pixels, and one cut in half.
fs::path huge_jpeg(const fs::path& dir) {
    std::string jpg = bytes_of(test::test_data("photos/two_point_shirt_s3_half.jpg"));
    const std::size_t sof = jpg.find("\xff\xc0");
    EXPECT_NE(sof, std::string::npos);
    jpg[sof + 5] = jpg[sof + 6] = jpg[sof + 7] = jpg[sof + 8] = '\xff';
    std::ofstream(dir / "huge.jpg", std::ios::binary) << jpg;
    return dir / "huge.jpg";
}

// A PNG whose IHDR claims 100000 x 100000 pixels (CRC fixed, so only the size is wrong).
fs::path huge_png(const fs::path& dir) {
    std::string png = bytes_of(fs::path(FOLDCAST_SOURCE_DIR) / "tests/golden/default.png");
    const std::uint32_t side = __builtin_bswap32(100000u);
    std::memcpy(png.data() + 16, &side, 4);
    std::memcpy(png.data() + 20, &side, 4);
    const std::uint32_t crc = __builtin_bswap32(codec::crc32(std::string_view(png.data() + 12, 17)));
    std::memcpy(png.data() + 29, &crc, 4);
    std::ofstream(dir / "huge.png", std::ios::binary) << png;
    return dir / "huge.png";
}

// Item 6: our one line naming the file, and `diff`'s unreadable-file status 4.
TEST_F(BadInput, ImagesWithHugeHeadersOrCutShortAreOurErrors) {
    const std::string supports = "197.5,50,357.5,48.5";
    const fs::path jpg = huge_jpeg(dir_), png = huge_png(dir_);
    const std::string photo = bytes_of(test::test_data("photos/two_point_shirt_s3_half.jpg"));
    const fs::path cut_jpg = write("cut.jpg", photo.substr(0, photo.size() / 2));
    const std::string golden = bytes_of(fs::path(FOLDCAST_SOURCE_DIR) / "tests/golden/default.png");
    const fs::path cut_png = write("cut.png", golden.substr(0, golden.size() / 2));
    const fs::path out = dir_ / "out.png";
    // A cut-short JPEG decodes (libjpeg fills the rest with grey): our warning names it.
    const test::Outcome cut = run({"folds", cut_jpg.string(), "-o", out.string(), "--supports", supports});
    EXPECT_TRUE(cut.exited && (cut.exit_code == 0 || cut.exit_code == 2)) << cut.err;
    expect_only_our_lines(cut, "folds cut.jpg");
    EXPECT_NE(cut.err.find(cut_jpg.string()), std::string::npos) << cut.err;
    for (const fs::path& bad : {jpg, png, cut_png}) {
        expect_refused({"folds", bad.string(), "-o", out.string(), "--supports", supports}, 2, bad.string());
        expect_refused({"overlay", bad.string(), "-o", out.string(), "--supports", supports, "--scale-px-per-m", "400"},
                       2, bad.string());
        expect_refused({"diff", bad.string(), bad.string()}, 4, bad.string());
    }
    const fs::path scene =
        write("textured.toml", "look = { base = \"linen\", appearance = { texture = \"" + png.string() + "\" } }\n");
    expect_refused({"render", scene.string(), "-o", out.string(), "--width", "16", "--height", "16", "--spp", "1"}, 2,
                   png.string());
}

TEST_F(BadInput, UnknownSubcommandIsNamed) { expect_refused({"bogus"}, 2, "bogus"); }

// Items 5 and 7 on the render side.
TEST_F(BadInput, ScenesAndValuesThatUsedToBeAccepted) {
    const std::string out = (dir_ / "out.png").string();
    const std::vector<std::string> small = {"--width", "16", "--height", "16", "--spp", "1"};
    auto with = [&](std::vector<std::string> args) {
        args.insert(args.end(), small.begin(), small.end());
        return args;
    };
    fs::create_directories(dir_ / "scene_dir");
    const std::string directory = (dir_ / "scene_dir").string();
    expect_refused(with({"render", directory, "-o", out}), 2, directory);
    expect_refused({"preview", directory, "-o", out}, 2, directory);
    expect_refused({"turntable", directory, "-o", (dir_ / "spin.mp4").string()}, 2, directory);
    const std::string scene = std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml";
    expect_refused(with({"render", scene, "-o", out, "--seed", "-1"}), 2, "--seed");
    expect_refused({"turntable", scene, "-o", (dir_ / "spin.mp4").string(), "--frames", "0:4/0"}, 2, "--frames");
    const fs::path grid = write("grid.toml", "[garment]\ngrid = [16.5, 24]\n");
    expect_refused(with({"render", grid.string(), "-o", out}), 2, "grid");
    const fs::path obj = write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    const fs::path nan_scene = write("nan.toml", "[garment]\npath = \"nan.obj\"\n");
    expect_refused(with({"render", nan_scene.string(), "-o", out}), 2, "nan.obj");
    EXPECT_FALSE(fs::exists(out)) << "a refused render wrote its output";
    (void)obj;
}

TEST_F(BadInput, ManifestValuesThatUsedToBeIgnored) {
    const fs::path wrong_dir =
        write("dir.toml", "output_dir = 5\nlooks = [\"linen\"]\n[[garments]]\nname = \"a\"\nscene = \"" +
                              std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml\"\n");
    expect_refused({"batch", wrong_dir.string(), "--quiet"}, 2, "output_dir");
    const fs::path dot = write("dot.toml",
                               "output_dir = \"cat\"\nwidth = 16\nheight = 16\nspp = 1\nlooks = [\"linen\"]\n"
                               "[[garments]]\nname = \"a\"\nscene = \".\"\n");
    expect_refused({"batch", dot.string(), "--quiet"}, 2, "scene");
    EXPECT_FALSE(fs::exists(dir_ / "cat" / "a" / "linen" / "front.png")) << "the default scene was rendered";
}

// An output that is one of the inputs: a render over its own texture replaced the texture,
// an encode over its own .fca re-encoded it lossily in place (both exit 0).
TEST_F(BadInput, RenderAndEncodeRefuseToOverwriteTheirInputs) {
    fs::copy_file(fs::path(FOLDCAST_SOURCE_DIR) / "tests/golden/default.png", dir_ / "tex.png");
    const fs::path scene =
        write("tex.toml", "look = { base = \"linen\", appearance = { texture = \"" + (dir_ / "tex.png").string() +
                              "\" } }\n[garment]\ngrid = [9, 9]\n");
    const std::string texture = bytes_of(dir_ / "tex.png");
    expect_refused({"render", scene.string(), "-o", (dir_ / "tex.png").string(), "--width", "16", "--height", "16",
                    "--spp", "1", "--quiet"},
                   2, "-o");
    EXPECT_EQ(bytes_of(dir_ / "tex.png"), texture) << "the texture was replaced";
    const std::string pc2 = (dir_ / "a.pc2").string(), fca = (dir_ / "a.fca").string();
    ASSERT_EQ(run({"drape", "--grid", "5x5", "--frames", "3", "-q", "-o", pc2}).exit_code, 0);
    ASSERT_EQ(run({"encode", pc2, "-q", "-o", fca}).exit_code, 0);
    const std::string encoded = bytes_of(fca);
    expect_refused({"encode", fca, "-q", "-o", fca}, 2, "-o");
    EXPECT_EQ(bytes_of(fca), encoded) << "the input was re-encoded in place";
}

// The first line names what the user gave, in the user's words: the flag (not the library's
// young_pa or keep_fraction), the file, and a value short enough to read (a vertex at 1e30
// was printed with 31 digits and six decimals; a --tile of 11 digits came back as another
// number, without the flag).
TEST_F(BadInput, FirstLinesNameTheFlagOrFileGiven) {
    const std::string pc2 = (dir_ / "a.pc2").string(), fca = (dir_ / "a.fca").string();
    ASSERT_EQ(run({"drape", "--grid", "5x5", "--frames", "3", "-q", "-o", pc2}).exit_code, 0);
    const std::string photo = test::test_data("photos/two_point_shirt_s3_half.jpg").string();
    const std::string out = (dir_ / "out.png").string();
    expect_refused({"drape", "--width-m", "1e308", "-o", (dir_ / "o.obj").string()}, 2, "--width-m");
    expect_refused({"drape", "--width-m", "3e9", "-q", "-o", (dir_ / "o.obj").string()}, 2, "--width-m");
    expect_refused({"overlay", photo, "-o", out, "--supports", "197.5,50,357.5,48.5", "--scale-px-per-m", "400",
                    "--young-mpa", "1e-9"},
                   2, "--young-mpa");
    expect_refused({"encode", pc2, "-q", "-o", fca, "--keep", "2"}, 2, "--keep");
    expect_refused({"encode", pc2, "-q", "-o", fca, "--keep", "0.5"}, 2, "--keep");
    expect_refused({"looks", "--swatches", out, "--tile", "99999999999x10"}, 2, "--tile '99999999999x10'");
    expect_refused({"looks", "--swatches", out, "--tile", "8x8"}, 2, "--tile");
    write("far.obj", "v 0 0 0\nv 1 0 0\nv 1e30 1 0\nf 1 2 3\n");
    const fs::path scene = write("far.toml", "[garment]\npath = \"far.obj\"\n");
    const test::Outcome o = run({"render", scene.string(), "-o", out, "--width", "16", "--height", "16", "--spp", "1"});
    EXPECT_EQ(o.exit_code, 2) << o.err;
    const std::string first = o.err.substr(0, o.err.find('\n'));
    EXPECT_NE(first.find("far.obj: vertex 2 lies 1e+30 from the origin"), std::string::npos) << first;
    EXPECT_FALSE(fs::exists(out));
}

// preview, looks --swatches and batch estimate their memory and time before any work, as
// render does: refused with the estimate (exit 2), nothing written, --force offered.
TEST_F(BadInput, PreviewSwatchesAndBatchAreRefusedUpFrontBeyondTheMachine) {
    const fs::path scene = write("tiny.toml", "[garment]\ngrid = [9, 9]\n");
    const std::string out = (dir_ / "out.png").string();
    expect_refused({"preview", scene.string(), "-o", out, "--width", "16384", "--height", "16384", "--msaa", "16"}, 2,
                   "preview " + out + " (16384x16384, --msaa 16) needs about");
    expect_refused({"looks", "--swatches", out, "--only", "linen", "--tile", "4096x4096", "--spp", "65536"}, 2,
                   "billion samples");
    EXPECT_FALSE(fs::exists(out));
    const std::string header = "output_dir = \"cat\"\nlooks = [\"linen\", \"denim\"]\n";
    const std::string garment = "[[garments]]\nname = \"a\"\nscene = \"tiny.toml\"\n";
    const fs::path huge = write("huge.toml", "width = 4096\nheight = 4096\nspp = 65536\n" + header + garment);
    expect_refused({"batch", huge.string(), "--quiet"}, 2, "huge.toml: width = 4096, height = 4096, spp = 65536");
    // Each image within a day, the shard's 48 beyond a week: more shards are the answer.
    std::string views;
    for (int v = 0; v < 24; ++v) views += "[[views]]\nname = \"v" + std::to_string(v) + "\"\n";
    const fs::path week = write("week.toml", "width = 1024\nheight = 1024\nspp = 16384\n" + header + garment + views);
    expect_refused({"batch", week.string(), "--quiet"}, 2, "more shards (--shard I/N)");
    EXPECT_FALSE(fs::exists(dir_ / "cat")) << "a refused batch made its catalogue";
    for (const char* command : {"preview", "looks", "batch"})
        EXPECT_NE(test::run_command(test::foldcast_under_test() + " " + command + " --help").out.find("--force"),
                  std::string::npos)
            << command << " --help lists no --force";
}

}  // namespace
}  // namespace foldcast
