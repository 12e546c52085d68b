// `foldcast drape`: JSON report, outputs (OBJ, PLY, PC2 round trip) and exit status 2 with
// one line naming the flag for bad input, leaving nothing behind.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "foldcast/core/mesh_io.hpp"
#include "foldcast/drape/drape.hpp"
#include "run_command.hpp"
#include "test_paths.hpp"

namespace fs = std::filesystem;

namespace {
struct Result {
    int status = -1;
    std::string out, err;
};

// `foldcast drape --quiet ARGUMENTS` run in `dir`, stdout and stderr apart.
Result run(const std::string& arguments, const fs::path& dir) {
    const fs::path err = dir / "stderr.txt";
    const foldcast::test::CommandResult ran =
        foldcast::test::run_command("cd '" + dir.string() + "' && " + foldcast::test::foldcast_binary() +
                                    " drape --quiet " + arguments + " 2> '" + err.string() + "'");
    Result result{ran.exit_code, ran.out, {}};
    std::ifstream in(err);
    result.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    in.close();
    fs::remove(err);
    return result;
}

std::size_t file_count(const fs::path& dir) {
    return std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}
}  // namespace

TEST(DrapeCli, JsonReportMatchesTheLibrary) {
    const fs::path dir = foldcast::test::temp_dir();
    const Result r =
        run("--json --verbose --width-m 0.6 --height-m 0.9 --inset-m 0.12 --thickness-mm 0.25 "
            "--young-mpa 4 --gsm 180 --grid 24x30",
            dir);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    foldcast::looks::Mechanics m;
    m.thickness_mm = 0.25;
    m.young_mpa = 4;
    m.gsm = 180;
    const auto s = foldcast::drape::solve_folds(foldcast::drape::cloth_from_look(m, 0.6, 0.9, 0.12));
    EXPECT_EQ(j["folds"].get<int>(), s.folds);
    EXPECT_GT(s.folds, 0);
    EXPECT_DOUBLE_EQ(j["Q"].get<double>(), s.Q);
    EXPECT_DOUBLE_EQ(j["zmax_m"].get<double>(), s.zmax_m);
    EXPECT_EQ(j["amplitudes_m"].get<std::vector<double>>(), s.amplitudes_m);
    EXPECT_EQ(j["feasible_folds"].get<std::vector<int>>(), s.feasible_folds);
    EXPECT_LE(j["residual"].get<double>(), 1e-9);
    EXPECT_GT(j["stretch_max"].get<double>(), j["stretch_mean"].get<double>());
    EXPECT_EQ(j["regime"], "wrinkled");
    EXPECT_EQ(j["candidates"].size(), s.candidates.size());
    EXPECT_EQ(file_count(dir), 0u);  // no -o: nothing written
}

// The report gives the stretch of the model's surface and of the relaxed grid; --no-relax
// writes the model's surface itself (the library's garment with relax = false).
TEST(DrapeCli, ReportsStretchBeforeAndAfterRelaxationAndNoRelaxKeepsTheModel) {
    const fs::path dir = foldcast::test::temp_dir();
    const Result relaxed = run("--json --grid 32x32", dir);
    ASSERT_EQ(relaxed.status, 0) << relaxed.err;
    const auto j = nlohmann::json::parse(relaxed.out);
    EXPECT_TRUE(j["relaxed"].get<bool>());
    EXPECT_LE(j["stretch_mean"].get<double>(), 0.005);
    EXPECT_LE(j["stretch_max"].get<double>(), 0.03);
    EXPECT_GT(j["stretch_before_relax"]["mean"].get<double>(), 0.05);  // the model's rows are too long
    EXPECT_GT(j["relax_iterations"].get<int>(), 0);

    const Result kept = run("--json --grid 32x32 --no-relax -o model.obj", dir);
    ASSERT_EQ(kept.status, 0) << kept.err;
    const auto k = nlohmann::json::parse(kept.out);
    EXPECT_FALSE(k["relaxed"].get<bool>());
    EXPECT_EQ(k["stretch_mean"], j["stretch_before_relax"]["mean"]);
    EXPECT_EQ(k["relax_iterations"].get<int>(), 0);
    const auto p = foldcast::drape::cloth_from_look(foldcast::looks::Mechanics{}, 0.5, 0.7, 0.1);  // the CLI's defaults
    const auto model = foldcast::drape::build_garment(p, foldcast::drape::solve_folds(p), {32, 32}, false);
    const foldcast::Mesh obj = foldcast::read_obj(dir / "model.obj");
    ASSERT_EQ(obj.positions.size(), model.mesh.positions.size());
    for (std::size_t v = 0; v < obj.positions.size(); ++v)
        EXPECT_LT((obj.positions[v] - model.mesh.positions[v]).norm(), 1e-6f) << v;  // OBJ's 7 digits
}

TEST(DrapeCli, DefaultsWriteAGarmentObjAndPly) {
    const fs::path dir = foldcast::test::temp_dir();
    ASSERT_EQ(run("-o garment.obj", dir).status, 0);
    const foldcast::Mesh obj = foldcast::read_obj(dir / "garment.obj");
    EXPECT_EQ(obj.positions.size(), 64u * 64u);
    EXPECT_EQ(obj.topology.uvs.size(), obj.positions.size());
    EXPECT_NEAR(obj.topology.uvs.back().x(), 0.5, 1e-6);  // UVs in metres
    ASSERT_EQ(run("-o garment.ply --grid 10x12", dir).status, 0);
    EXPECT_GT(fs::file_size(dir / "garment.ply"), 10u * 12u * 32u);
}

TEST(DrapeCli, Pc2RoundTrip) {
    const fs::path dir = foldcast::test::temp_dir();
    const Result r = run("-o anim.pc2 --frames 7 --fps 24 --grid 9x11 --sway-m 0.01", dir);
    ASSERT_EQ(r.status, 0) << r.err;
    const foldcast::Animation anim = foldcast::read_pc2_animation(dir / "anim.pc2", dir / "anim.obj", 24.0);
    ASSERT_EQ(anim.frame_count(), 7u);
    ASSERT_EQ(anim.vertex_count(), 99u);
    foldcast::drape::AnimationOptions options;
    options.frames = 7;
    options.fps = 24;
    options.sway_amplitude_m = 0.01;
    // The CLI's defaults: a cotton shirting panel (looks::Mechanics defaults), 0.5 x 0.7 m, inset 0.1.
    const auto params = foldcast::drape::cloth_from_look(foldcast::looks::Mechanics{}, 0.5, 0.7, 0.1);
    const foldcast::Animation expected = foldcast::drape::animate(params, {9, 11}, options);
    for (std::size_t f = 0; f < 7; ++f) EXPECT_TRUE(anim.frames[f] == expected.frames[f]) << "frame " << f;
    EXPECT_EQ(anim.topology.triangles, expected.topology.triangles);
}

TEST(DrapeCli, BadInputExitsTwoNamingTheFlagAndWritesNothing) {
    const fs::path dir = foldcast::test::temp_dir();
    const std::pair<const char*, const char*> cases[] = {
        {"--width-m 0 -o g.obj", "--width-m"},
        {"--height-m -0.5 -o g.obj", "--height-m"},
        {"--inset-m 0.25 -o g.obj", "--inset-m"},
        {"--thickness-mm 0 -o g.obj", "--thickness-mm"},
        {"--young-mpa nan -o g.obj", "--young-mpa"},
        {"--gsm inf -o g.obj", "--gsm"},
        {"--weight-n-mm2 -1 -o g.obj", "--weight-n-mm2"},
        {"--gsm 100 --weight-n-mm2 1e-6 -o g.obj", "--weight-n-mm2"},
        {"--poisson 0.5 -o g.obj", "--poisson"},
        {"--grid 1x9 -o g.obj", "--grid"},
        {"--frames 0 -o g.pc2", "--frames"},
        {"--no-such-flag 1 -o g.obj", "--no-such-flag"},
        {"-o g.stl", ".stl"},
        {"-o missing_dir/g.obj", "missing_dir"},
        {"--look no_such_look -o g.obj", "no_such_look"},
        {"--closure papers -o g.obj", "--closure"},
    };
    for (const auto& [args, named] : cases) {
        const Result r = run(args, dir);
        EXPECT_EQ(r.status, 2) << args;
        EXPECT_NE(r.err.find(named), std::string::npos) << args << ": " << r.err;
        EXPECT_TRUE(r.out.empty()) << args;
        EXPECT_EQ(file_count(dir), 0u) << args;
    }
}

TEST(DrapeCli, LookGivesTheMechanicsAndFlagsOverrideIt) {
    const fs::path dir = foldcast::test::temp_dir();
    const Result look = run("--look denim --json", dir);
    ASSERT_EQ(look.status, 0) << look.err;
    const auto j = nlohmann::json::parse(look.out);
    EXPECT_EQ(j["look"], "denim");
    const Result overridden = run("--look denim --thickness-mm 0.123 --json", dir);
    ASSERT_EQ(overridden.status, 0);
    const auto k = nlohmann::json::parse(overridden.out);
    EXPECT_DOUBLE_EQ(k["cloth"]["thickness_m"].get<double>(), 0.123e-3);
    EXPECT_EQ(k["cloth"]["young_pa"], j["cloth"]["young_pa"]);
    EXPECT_NE(k["cloth"]["thickness_m"], j["cloth"]["thickness_m"]);
}

// The paper's closure from the command line: the paper's Table 1, first row, and its name in
// the report; the default report names the hem closure.
TEST(DrapeCli, PaperClosureReproducesTheFirstTableRow) {
    const fs::path dir = foldcast::test::temp_dir();
    const Result r = run("--json --closure paper --width-m 1.4 --height-m 0.9 --inset-m 0.1 --thickness-mm 0.25 "
                         "--young-mpa 165 --weight-n-mm2 15e-7 --grid 24x24",
                         dir);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["closure"], "paper");
    EXPECT_EQ(j["folds"].get<int>(), 5);
    EXPECT_NEAR(j["Q"].get<double>(), 1.31, 0.05);
    EXPECT_NEAR(j["critical_Q"].get<double>(), 1.291, 0.001);
    const Result hem = run("--json --grid 24x24", dir);
    ASSERT_EQ(hem.status, 0) << hem.err;
    EXPECT_EQ(nlohmann::json::parse(hem.out)["closure"], "hem");
}

// Supports without --grid: the default 64 columns widened to the nearest count that puts
// every support on a vertex ((nu - 1) a multiple of the bays); two supports keep 64x64.
TEST(DrapeCli, SupportsWithoutGridPutEverySupportOnAVertex) {
    const fs::path dir = foldcast::test::temp_dir();
    const std::vector<std::pair<int, int>> supports_nu{{2, 64}, {3, 65}, {4, 64}, {5, 65}, {9, 65}, {11, 71}};
    for (const auto& [supports, nu] : supports_nu) {
        const Result r =
            run("--json --width-m 1.2 --height-m 1 --inset-m 0.08 --supports " + std::to_string(supports), dir);
        ASSERT_EQ(r.status, 0) << supports << ": " << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["grid"][0].get<int>(), nu) << supports;
        EXPECT_EQ(j["grid"][1].get<int>(), 64) << supports;
    }
    fs::remove_all(dir);
}

TEST(DrapeCli, SupportsAndDrop) {
    const fs::path dir = foldcast::test::temp_dir();
    const Result r =
        run("--json --supports 5 --support-drop-m 0.05 --width-m 1.2 --height-m 1 --inset-m 0.08 "
            "--grid 33x20 -o curtain.obj",
            dir);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["cloth"]["supports"].get<int>(), 5);
    EXPECT_DOUBLE_EQ(j["cloth"]["support_drop_m"].get<double>(), 0.05);
    EXPECT_GE(j["folds"].get<int>(), 1);
    EXPECT_LE(j["fold_length_m"].get<double>(), 1.0);
    EXPECT_TRUE(fs::exists(dir / "curtain.obj"));
    // A grid whose columns cannot put every support on a vertex, and bad counts: exit 2.
    for (const char* bad : {"--supports 5 --width-m 1.2 --grid 64x20", "--supports 1", "--supports 70",
                            "--support-drop-m 0.5", "--support-drop-m nan"}) {
        const Result e = run(bad, dir);
        EXPECT_EQ(e.status, 2) << bad << ": " << e.err;
        EXPECT_NE(e.err.find(std::string(bad).find("grid") != std::string::npos ? "grid" : "--support"),
                  std::string::npos)
            << bad << ": " << e.err;
    }
    fs::remove_all(dir);
}
