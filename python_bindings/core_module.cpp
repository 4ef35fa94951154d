// meshlab_symmetry._core: the detection core as a Python extension (pybind11), so that
// meshlab_symmetry.detect(..., engine="core") runs without pymeshlab in the loop and can
// report progress.  A thin adapter like the MeshLab filter: it converts arrays and options,
// calls symmetry::detect_partial_symmetries, and hands the result back as plain Python
// values; no step of the pipeline is here.
#include "core/detection.h"

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

namespace py = pybind11;
using namespace symmetry;

namespace {

// The options detect() takes, in the core's units (lengths as fractions of the bounding-box
// diagonal, min_patch_area as a fraction of the area), named as the filter's parameters.
DetectionOptions options_from(const py::dict& given) {
    DetectionOptions o;
    for (const auto& [key, value] : given) {
        const std::string name = py::str(key);
        if (name == "transformation_group") o.group = TransformationGroup(value.cast<int>());
        else if (name == "sample_count") o.sample_count = value.cast<int>();
        else if (name == "max_working_vertices") o.working.max_vertices = value.cast<int>();
        else if (name == "pair_sample_count") o.pair_sample_count = value.cast<int>();
        else if (name == "curvature_radius") o.curvature_radius = value.cast<double>();
        else if (name == "umbilic_ratio") o.umbilic_ratio = value.cast<double>();
        else if (name == "signature_tolerance") o.signature_tolerance = value.cast<double>();
        else if (name == "cluster_bandwidth") o.cluster_bandwidth = value.cast<double>();
        else if (name == "min_cluster_support") o.min_cluster_support = value.cast<int>();
        else if (name == "verification_tolerance") o.verification_tolerance = value.cast<double>();
        else if (name == "min_patch_area") o.min_patch_area = value.cast<double>();
        else if (name == "max_symmetries") o.max_symmetries = value.cast<int>();
        else if (name == "refine_with_icp") o.refine_with_icp = value.cast<bool>();
        else if (name == "reduce_basis") o.reduce_basis = value.cast<bool>();
        else if (name == "basis_loop_length") o.basis_loop_length = value.cast<int>();
        else if (name == "basis_tolerance") o.basis_tolerance = value.cast<double>();
        // As the filter does: any int is a valid seed, negative ones wrap.
        else if (name == "random_seed") o.random_seed = unsigned(value.cast<long long>());
        else if (name == "keep_transformation_space") o.keep_transformation_space = value.cast<bool>();
        else throw py::value_error("detect() has no parameter '" + name + "'");
    }
    return o;
}

py::dict symmetry_dict(const DetectedSymmetry& s) {
    py::dict d;
    d["matrix"] = Eigen::Matrix4d(s.transform.matrix());
    d["scale"] = s.transform.scale;
    d["is_reflection"] = s.transform.reflection;
    d["continuous_kind"] = int(s.continuous_kind);
    d["axis_point"] = Eigen::Vector3d(s.axis_point);
    d["axis_direction"] = Eigen::Vector3d(s.axis_direction);
    d["pitch"] = s.pitch;
    d["source_vertices"] = s.source_vertices;
    d["target_vertices"] = s.target_vertices;
    d["rms_error"] = s.rms_error;
    d["max_error"] = s.max_error;
    d["systematic_error"] = s.systematic_error;
    d["source_area"] = s.source_area;
    d["support"] = s.support;
    d["is_generator"] = s.is_generator;
    d["word"] = s.word;
    return d;
}

// The numbers the filter returns beside the symmetries, under the filter's names.
py::dict work_dict(const DetectionResult& r) {
    py::dict w;
    w["generator_count"] = r.generator_count;
    w["samples"] = r.samples;
    w["pruned_samples"] = r.pruned_samples;
    w["pairs"] = r.pairs;
    w["clusters"] = r.clusters;
    w["verified_clusters"] = r.verified_candidates;
    w["working_vertices"] = r.working_vertices;
    w["welded_vertices"] = r.welded_vertices;
    w["point_cloud"] = r.point_cloud;
    w["normals_estimated"] = r.normals_estimated;
    w["flipped_faces"] = r.flipped_faces;
    w["repeated_faces"] = r.repeated_faces;
    w["back_faces"] = r.back_faces;
    w["noise"] = r.noise;
    w["smoothing_radius"] = r.smoothing_radius;
    w["curvature_radius_used"] = r.curvature_radius;
    w["pair_sample_count_used"] = r.pairs_sample_count_used;
    return w;
}

py::dict detect(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const py::dict& parameters,
                const std::function<void(int, const std::string&)>& progress) {
    const DetectionOptions options = options_from(parameters);
    Progress report;
    if (progress)
        report = [&progress](int percent, const char* stage) {
            // The core calls back on this thread; the callback is Python, so it takes the
            // GIL, and a KeyboardInterrupt raised in it (or pending) stops the run.
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            progress(percent, stage);
        };
    DetectionResult r;
    {
        py::gil_scoped_release release;  // other Python threads run while the core works
        // No faces: a point cloud, whose normals the core estimates (as the filter does for a
        // cloud without normals).
        r = F.rows() == 0 && V.rows() > 0
                ? detect_partial_symmetries_in_point_cloud(V, Eigen::MatrixX3d(0, 3), options, report)
                : detect_partial_symmetries(V, F, options, report);
    }
    py::list symmetries;
    for (const DetectedSymmetry& s : r.symmetries) symmetries.append(symmetry_dict(s));
    py::dict out;
    out["symmetries"] = symmetries;
    // Copied into numpy arrays (a list of a million floats would be slow to make).
    out["deviation"] = py::array_t<double>(py::ssize_t(r.vertex_deviation.size()), r.vertex_deviation.data());
    out["symmetry_id"] = py::array_t<int>(py::ssize_t(r.vertex_symmetry_id.size()), r.vertex_symmetry_id.data());
    out["timings"] = py::dict(py::arg("seconds_signatures") = r.seconds_signatures,
                              py::arg("seconds_pairing") = r.seconds_pairing,
                              py::arg("seconds_clustering") = r.seconds_clustering,
                              py::arg("seconds_verification") = r.seconds_verification);
    out["work"] = work_dict(r);
    if (options.keep_transformation_space) {
        const TransformationSpaceSnapshot& g = r.transformation_space;
        py::dict gamma;
        gamma["points"] = g.points;
        gamma["improper"] = std::vector<bool>(g.improper.begin(), g.improper.end());
        gamma["modes"] = g.modes;
        gamma["mode_heights"] = g.mode_heights;
        gamma["mode_improper"] = std::vector<bool>(g.mode_improper.begin(), g.mode_improper.end());
        gamma["symmetries"] = g.symmetries;
        out["transformation_space"] = gamma;
    }
    return out;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
    m.doc() = "The symmetry-detection core (Mitra, Guibas, Pauly 2006) without pymeshlab; "
              "use meshlab_symmetry.detect(mesh, engine='core').";
    // The core's sentence for unusable input or parameters arrives as ValueError.
    py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
    m.def("detect", &detect, py::arg("vertices"), py::arg("faces"), py::arg("parameters"),
          py::arg("progress") = nullptr,
          "Runs the pipeline on (vertices #V x 3 float64, faces #F x 3 int32) with the parameters "
          "(a dict of detect()'s names, lengths as fractions of the diagonal); progress(percent, stage) "
          "is called on this thread.  Returns a dict of plain values.");
}
