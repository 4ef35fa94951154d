// Seeded fuzzing of the core's entry point (issue 10: hostile and broken input).
//
// Each case is a small mesh built from an analytic shape (or two copies of one, so the
// pipeline runs through pairing, clustering and verification) and then broken the ways
// exported and scanned files are broken: holes, flipped and duplicated faces, fins on an
// edge, duplicate and unreferenced vertices, zero-area faces, a triangle soup, coordinates
// around 1e8 or 1e-8, a NaN, a face index past the end; with parameters drawn inside their
// ranges and now and then just outside them.  Every case must end in one of two ways:
//   - a result whose numbers are finite and whose indices are in range, or
//   - an InputError (and it must, for a NaN, a bad index or a parameter out of range).
// Anything else (another exception, a NaN in the result, a crash) is a finding.  Built with
// SYMMETRY_SANITIZE (make test-sanitize), memory and undefined-behaviour errors are findings
// too.  Every third case also runs twice and must give the same result (random_seed).
//
// The meshes in tests/fuzz_corpus (OFF, with the options in "# option" comment lines) run
// first: cases that once failed, kept as regressions.  A failing case is written there as
// an OFF file (--save DIR) so that it becomes one.
//
// Usage: fuzz_detection [--cases N] [--seed S] [--corpus DIR] [--save DIR] [--verbose 1]
#include "core/detection.h"
#include "core/mesh.h"
#include "test_shapes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace symmetry;
using namespace symmetry::testing;

namespace {

struct Case {
    std::string name;
    Shape mesh;
    DetectionOptions options;
    bool must_refuse = false;  // a NaN, a bad index or a parameter out of range
};

// ---------------------------------------------------------------- the meshes

Shape base_shape(std::mt19937& rng) {
    std::uniform_int_distribution<int> pick(0, 4);
    switch (pick(rng)) {
    case 0: return sphere(1.0, 1 + int(rng() % 2));
    case 1: return box(1.0, 0.6, 0.3, 1 + int(rng() % 3));
    case 2: return cylinder(0.5, 2.0, 6 + int(rng() % 20), 1 + int(rng() % 6));
    case 3: return torus(2.0, 0.5 + 0.3 * double(rng() % 3), 8 + int(rng() % 16), 6 + int(rng() % 8));
    default: return deformed_torus(2.0, 1.0, 24, 12, [](double u) { return 0.6 + 0.25 * std::cos(u); });
    }
}

// Two copies of a shape, the second moved by a random rigid motion (reflected half the
// time): a planted symmetry, so that the broken mesh still gets through every stage.
Shape planted_pair(std::mt19937& rng) {
    const Shape base = base_shape(rng);
    std::uniform_real_distribution<double> unit(-1, 1);
    Eigen::Matrix3d A = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng) + 1.5).normalized().toRotationMatrix();
    if (rng() % 2) A.col(0) *= -1;
    return merged(base, transformed(base, A, Eigen::Vector3d(6, unit(rng), unit(rng))));
}

void remove_faces(Shape& s, std::mt19937& rng, double share) {
    std::vector<Eigen::Vector3i> kept;
    std::bernoulli_distribution drop(share);
    for (Eigen::Index f = 0; f < s.F.rows(); ++f)
        if (!drop(rng)) kept.push_back(s.F.row(f));
    if (kept.empty()) kept.push_back(s.F.row(0));
    s.F.resize(Eigen::Index(kept.size()), 3);
    for (size_t f = 0; f < kept.size(); ++f) s.F.row(Eigen::Index(f)) = kept[f];
}

void flip_faces(Shape& s, std::mt19937& rng, double share) {
    std::bernoulli_distribution flip(share);
    for (Eigen::Index f = 0; f < s.F.rows(); ++f)
        if (flip(rng)) std::swap(s.F(f, 1), s.F(f, 2));
}

void append_faces(Shape& s, const std::vector<Eigen::Vector3i>& faces) {
    const Eigen::Index n = s.F.rows();
    s.F.conservativeResize(n + Eigen::Index(faces.size()), 3);
    for (size_t i = 0; i < faces.size(); ++i) s.F.row(n + Eigen::Index(i)) = faces[i];
}

Eigen::Index append_vertex(Shape& s, const Eigen::Vector3d& p) {
    s.V.conservativeResize(s.V.rows() + 1, 3);
    s.V.row(s.V.rows() - 1) = p;
    return s.V.rows() - 1;
}

// Faces repeated, faces with a repeated corner, and fins: a third face on an existing edge
// (a non-manifold edge) with its apex off the surface.
void add_degenerate_and_non_manifold_faces(Shape& s, std::mt19937& rng, int count) {
    std::vector<Eigen::Vector3i> extra;
    for (int i = 0; i < count; ++i) {
        const Eigen::Vector3i f = s.F.row(Eigen::Index(rng() % s.F.rows()));
        switch (rng() % 3) {
        case 0: extra.push_back(f); break;
        case 1: extra.emplace_back(f[0], f[0], f[1]); break;
        default: {
            const Eigen::Vector3d apex = s.V.row(f[0]) + 0.3 * (s.V.row(f[1]) - s.V.row(f[2]));
            extra.emplace_back(f[0], f[1], int(append_vertex(s, apex + Eigen::Vector3d(0, 0, 0.2))));
        }
        }
    }
    append_faces(s, extra);
}

// Vertices that no face uses, and copies of used ones that some faces are moved onto.
void add_duplicate_and_unreferenced_vertices(Shape& s, std::mt19937& rng, int count) {
    for (int i = 0; i < count; ++i) {
        const Eigen::Index v = Eigen::Index(rng() % s.V.rows());
        const Eigen::Index copy = append_vertex(s, s.V.row(v));
        if (rng() % 2) continue;  // unreferenced
        for (Eigen::Index f = 0; f < s.F.rows(); ++f)
            for (int c = 0; c < 3; ++c)
                if (s.F(f, c) == v && rng() % 2) s.F(f, c) = int(copy);
    }
}

// Every triangle with its own three vertices, as STL files and numpy pipelines have it.
void make_soup(Shape& s) {
    Eigen::MatrixX3d V(s.F.rows() * 3, 3);
    Eigen::MatrixX3i F(s.F.rows(), 3);
    for (Eigen::Index f = 0; f < s.F.rows(); ++f)
        for (int c = 0; c < 3; ++c) {
            V.row(3 * f + c) = s.V.row(s.F(f, c));
            F(f, c) = int(3 * f + c);
        }
    s.V = V;
    s.F = F;
}

void move_far_or_shrink(Shape& s, std::mt19937& rng) {
    const double scale = std::pow(10.0, double(int(rng() % 17)) - 8);  // 1e-8 .. 1e8
    const double offset = (rng() % 2) ? 1e8 : 0.0;
    s.V = (s.V * scale).rowwise() + Eigen::RowVector3d(offset, -offset, 0);
}

void add_noise(Shape& s, std::mt19937& rng, double amplitude) {
    std::normal_distribution<double> gauss(0, amplitude);
    for (Eigen::Index i = 0; i < s.V.rows(); ++i)
        for (int c = 0; c < 3; ++c) s.V(i, c) += gauss(rng);
}

// --------------------------------------------------------------- the options

DetectionOptions random_options(std::mt19937& rng) {
    DetectionOptions o;
    std::uniform_real_distribution<double> u(0, 1);
    o.group = TransformationGroup(int(rng() % 4));
    o.sample_count = 100 + int(rng() % 1500);
    o.pair_sample_count = (rng() % 3 == 0) ? 1 + int(rng() % o.sample_count) : 0;
    o.curvature_radius = 0.005 + 0.1 * u(rng);
    o.verification_tolerance = 0.002 + 0.05 * u(rng);
    o.min_patch_area = 0.001 + 0.3 * u(rng);
    o.max_symmetries = 1 + int(rng() % 30);
    o.refine_with_icp = rng() % 4 != 0;
    o.reduce_basis = rng() % 4 != 0;
    o.random_seed = unsigned(rng());
    return o;
}

// One parameter just outside its range (or not a number): the filter must refuse it.
void break_one_option(DetectionOptions& o, std::mt19937& rng) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    switch (rng() % 7) {
    case 0: o.sample_count = -int(rng() % 3); break;
    case 1: o.curvature_radius = (rng() % 2) ? -0.01 : nan; break;
    case 2: o.verification_tolerance = (rng() % 2) ? 0.0 : nan; break;
    case 3: o.min_patch_area = (rng() % 2) ? -0.01 : 1.5; break;
    case 4: o.max_symmetries = 0; break;
    case 5: o.cluster_bandwidth = (rng() % 2) ? 0.0 : -1.0; break;
    default: o.umbilic_ratio = (rng() % 2) ? 0.0 : 1.5; break;
    }
}

// ---------------------------------------------------------------- the cases

// The structural breakage: each kind with some probability, several at once.
void break_mesh(Shape& m, std::mt19937& rng, std::ostringstream& name) {
    std::bernoulli_distribution often(0.35);
    if (often(rng)) { remove_faces(m, rng, 0.02 + 0.3 * double(rng() % 100) / 100); name << " holes"; }
    if (often(rng)) { flip_faces(m, rng, 0.5); name << " flipped"; }
    if (often(rng)) { add_degenerate_and_non_manifold_faces(m, rng, 1 + int(rng() % 20)); name << " degenerate+fins"; }
    if (often(rng)) { add_duplicate_and_unreferenced_vertices(m, rng, 1 + int(rng() % 30)); name << " duplicates"; }
    if (often(rng)) { add_noise(m, rng, 0.003 * double(rng() % 10)); name << " noise"; }
    if (rng() % 6 == 0) { make_soup(m); name << " soup"; }
    if (rng() % 5 == 0) { move_far_or_shrink(m, rng); name << " rescaled"; }
}

// The breakage the filter must refuse: a NaN, an index past the end, a bad parameter.
bool break_beyond_repair(Case& c, std::mt19937& rng, std::ostringstream& name) {
    switch (rng() % 12) {
    case 0:
        c.mesh.V(Eigen::Index(rng() % c.mesh.V.rows()), int(rng() % 3)) =
            (rng() % 2) ? std::numeric_limits<double>::quiet_NaN() : std::numeric_limits<double>::infinity();
        name << " nan";
        return true;
    case 1:
        c.mesh.F(Eigen::Index(rng() % c.mesh.F.rows()), int(rng() % 3)) = (rng() % 2) ? -1 : int(c.mesh.V.rows());
        name << " bad-index";
        return true;
    case 2: break_one_option(c.options, rng); name << " bad-option"; return true;
    default: return false;
    }
}

Case random_case(unsigned seed) {
    std::mt19937 rng(seed);
    Case c;
    std::ostringstream name;
    name << "seed " << seed << ":";
    c.mesh = (rng() % 3 == 0) ? base_shape(rng) : planted_pair(rng);
    c.options = random_options(rng);
    break_mesh(c.mesh, rng, name);
    c.must_refuse = break_beyond_repair(c, rng, name);
    c.name = name.str();
    return c;
}

// --------------------------------------------------------- checking a result

bool finite_in(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }

bool increasing_in_range(const std::vector<int>& rows, Eigen::Index n) {
    for (size_t i = 0; i < rows.size(); ++i)
        if (rows[i] < 0 || rows[i] >= n || (i > 0 && rows[i] <= rows[i - 1])) return false;
    return true;
}

// What every result must satisfy, whatever the mesh: a non-empty string says what is wrong.
std::string defect_of(const DetectionResult& r, const Case& c) {
    const Eigen::Index n = c.mesh.V.rows();
    // max_symmetries discrete symmetries at most, and as many continuous families besides them.
    const auto families = std::count_if(r.symmetries.begin(), r.symmetries.end(), [](const DetectedSymmetry& s) {
        return s.continuous_kind != ContinuousKind::Discrete;
    });
    if (Eigen::Index(r.symmetries.size()) - families > c.options.max_symmetries)
        return "more discrete symmetries than max_symmetries";
    if (families > c.options.max_symmetries) return "more continuous families than max_symmetries";
    if (Eigen::Index(r.vertex_deviation.size()) != n || Eigen::Index(r.vertex_symmetry_id.size()) != n)
        return "per-vertex outputs not one per input vertex";
    for (Eigen::Index v = 0; v < n; ++v) {
        if (!std::isfinite(r.vertex_deviation[size_t(v)])) return "a vertex deviation is not finite";
        const int id = r.vertex_symmetry_id[size_t(v)];
        if (id < -1 || id >= int(r.symmetries.size())) return "a symmetry_id out of range";
    }
    for (const DetectedSymmetry& s : r.symmetries) {
        if (!s.transform.matrix().allFinite()) return "a transform is not finite";
        if (!finite_in(s.rms_error, 0, 1e3) || !finite_in(s.max_error, 0, 1e3) || !finite_in(s.systematic_error, 0, 1e3))
            return "an error figure is not finite";
        if (!finite_in(s.source_area, 0, 1 + 1e-9)) return "a source area outside [0, 1]";
        if (!increasing_in_range(s.source_vertices, n) || !increasing_in_range(s.target_vertices, n))
            return "patch vertices out of range or not increasing";
    }
    return "";
}

bool same_result(const DetectionResult& a, const DetectionResult& b) {
    if (a.symmetries.size() != b.symmetries.size() || a.vertex_symmetry_id != b.vertex_symmetry_id) return false;
    for (size_t i = 0; i < a.symmetries.size(); ++i)
        if (a.symmetries[i].transform.matrix() != b.symmetries[i].transform.matrix() ||
            a.symmetries[i].source_vertices != b.symmetries[i].source_vertices)
            return false;
    return true;
}

// How a case went: what went wrong (empty when it went as it must), whether the filter
// refused it with an InputError, and its result when it did not.
struct Outcome {
    std::string defect;
    bool refused = false;
    DetectionResult result;
};

// A coarse case with a small curvature_radius is analysed on a refined copy: kept to the
// fuzzed meshes' own sizes, so that a hundred cases stay within ctest's timeout, even under
// the sanitizers.  The refinement itself is fuzzed all the same.
constexpr int kMaxRefinedVertices = 3000;

Outcome run_case(const Case& c, bool twice) {
    Outcome o;
    DetectionOptions options = c.options;
    options.working.max_refined_vertices = kMaxRefinedVertices;
    try {
        o.result = detect_partial_symmetries(c.mesh.V, c.mesh.F, options);
        if (c.must_refuse) o.defect = "accepted input it must refuse";
        else o.defect = defect_of(o.result, c);
        if (o.defect.empty() && twice && !same_result(o.result, detect_partial_symmetries(c.mesh.V, c.mesh.F, options)))
            o.defect = "two runs with the same random_seed differ";
    } catch (const InputError& e) {
        // Refused in a sentence: a right answer for broken input.
        o.refused = true;
        if (std::string(e.what()).empty()) o.defect = "an InputError without a sentence";
    } catch (const std::exception& e) {
        o.defect = std::string("an exception other than InputError: ") + e.what();
    }
    return o;
}

void print_case(const Case& c, const Outcome& o, double seconds) {
    const DetectionResult& r = o.result;
    std::cout << c.name << " (" << c.mesh.V.rows() << " vertices, group " << int(c.options.group) << "): "
              << (o.refused ? "refused" : "answered") << " in " << seconds << " s";
    if (!o.refused)
        std::cout << " [" << r.symmetries.size() << " symmetries, " << r.pruned_samples << " samples, " << r.pairs
                  << " pairs, " << r.clusters << " clusters; seconds " << r.seconds_signatures << " " << r.seconds_pairing
                  << " " << r.seconds_clustering << " " << r.seconds_verification << "]";
    std::cout << "\n";
}

// ------------------------------------------------- the corpus, in OFF files

void save_case(const Case& c, const std::string& dir, unsigned seed) {
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/case_" + std::to_string(seed) + ".off";
    std::ofstream out(path);
    out.precision(17);
    out << "OFF\n# " << c.name << "\n";
    const DetectionOptions& o = c.options;
    out << "# option group " << int(o.group) << "\n# option sample_count " << o.sample_count
        << "\n# option pair_sample_count " << o.pair_sample_count << "\n# option curvature_radius " << o.curvature_radius
        << "\n# option verification_tolerance " << o.verification_tolerance << "\n# option min_patch_area "
        << o.min_patch_area << "\n# option max_symmetries " << o.max_symmetries << "\n# option refine_with_icp "
        << o.refine_with_icp << "\n# option reduce_basis " << o.reduce_basis << "\n# option random_seed "
        << o.random_seed << "\n# option must_refuse " << c.must_refuse << "\n";
    out << c.mesh.V.rows() << " " << c.mesh.F.rows() << " 0\n" << c.mesh.V << "\n";
    for (Eigen::Index f = 0; f < c.mesh.F.rows(); ++f) out << "3 " << c.mesh.F.row(f) << "\n";
    std::cerr << "  written to " << path << "\n";
}

void apply_option(Case& c, const std::string& key, double value) {
    DetectionOptions& o = c.options;
    if (key == "group") o.group = TransformationGroup(int(value));
    else if (key == "sample_count") o.sample_count = int(value);
    else if (key == "pair_sample_count") o.pair_sample_count = int(value);
    else if (key == "curvature_radius") o.curvature_radius = value;
    else if (key == "verification_tolerance") o.verification_tolerance = value;
    else if (key == "min_patch_area") o.min_patch_area = value;
    else if (key == "max_symmetries") o.max_symmetries = int(value);
    else if (key == "refine_with_icp") o.refine_with_icp = value != 0;
    else if (key == "reduce_basis") o.reduce_basis = value != 0;
    else if (key == "random_seed") o.random_seed = unsigned(value);
    else if (key == "must_refuse") c.must_refuse = value != 0;
    else throw std::runtime_error("unknown option " + key);
}

// Reads the OFF header comments as options, then the vertices and triangles.
Case load_case(const std::filesystem::path& path) {
    std::ifstream in(path);
    Case c;
    c.name = path.filename().string();
    std::string line;
    std::getline(in, line);  // OFF
    std::istringstream counts;
    while (std::getline(in, line)) {
        if (line.rfind("# option ", 0) == 0) {
            std::istringstream kv(line.substr(9));
            std::string key;
            double value = 0;
            kv >> key >> value;
            apply_option(c, key, value);
        } else if (!line.empty() && line[0] != '#') {
            counts.str(line);
            break;
        }
    }
    Eigen::Index nv = 0, nf = 0;
    counts >> nv >> nf;
    c.mesh.V.resize(nv, 3);
    c.mesh.F.resize(nf, 3);
    for (Eigen::Index v = 0; v < nv; ++v) in >> c.mesh.V(v, 0) >> c.mesh.V(v, 1) >> c.mesh.V(v, 2);
    for (Eigen::Index f = 0; f < nf; ++f) {
        int three = 0;
        in >> three >> c.mesh.F(f, 0) >> c.mesh.F(f, 1) >> c.mesh.F(f, 2);
    }
    if (!in) throw std::runtime_error("cannot read " + path.string());
    return c;
}

struct Arguments {
    int cases = 100;
    unsigned seed = 1;
    std::string corpus, save;
    bool verbose = false;  // one line per case with its seconds
};

Arguments parse(int argc, char** argv) {
    Arguments a;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        if (key == "--cases") a.cases = std::stoi(value);
        else if (key == "--seed") a.seed = unsigned(std::stoul(value));
        else if (key == "--corpus") a.corpus = value;
        else if (key == "--save") a.save = value;
        else if (key == "--verbose") a.verbose = value != "0";
        else throw std::runtime_error("unknown argument " + key);
    }
    return a;
}

int run_corpus(const std::string& dir) {
    int failures = 0;
    if (dir.empty() || !std::filesystem::is_directory(dir)) return 0;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().extension() == ".off") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& path : files) {
        const Case c = load_case(path);
        if (const Outcome o = run_case(c, true); !o.defect.empty()) {
            std::cerr << "FAIL corpus " << c.name << ": " << o.defect << "\n";
            ++failures;
        }
    }
    std::cout << files.size() << " corpus cases run\n";
    return failures;
}

}  // namespace

int main(int argc, char** argv) {
    const Arguments args = parse(argc, argv);
    int failures = run_corpus(args.corpus), must_refuse = 0, refused = 0;
    for (int i = 0; i < args.cases; ++i) {
        const unsigned seed = args.seed + unsigned(i);
        const Case c = random_case(seed);
        const auto start = std::chrono::steady_clock::now();
        const Outcome o = run_case(c, i % 3 == 0);
        if (args.verbose) print_case(c, o, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        if (!o.defect.empty()) {
            std::cerr << "FAIL " << c.name << ": " << o.defect << "\n";
            if (!args.save.empty()) save_case(c, args.save, seed);
            ++failures;
        }
        must_refuse += c.must_refuse;
        refused += o.refused;
    }
    std::cout << args.cases << " random cases run: " << refused << " refused in a sentence (" << must_refuse
              << " had to be), " << failures << " failures\n";
    return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
