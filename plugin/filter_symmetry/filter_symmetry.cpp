#include "filter_symmetry.h"

#include "filter_texts.h"
#include "host_mesh.h"
#include "symmetry_parameters.h"

#include <core/detection.h>
#include <core/symmetrization.h>

#include <Eigen/Core>
#include <algorithm>
#include <map>
#include <string>
#include <vector>

namespace {

using symmetry_host::Detection;

/// MeshLab's progress callback as the core's: the stage names go to the progress bar.
symmetry::Progress progressOf(vcg::CallBackPos* cb)
{
	if (cb == nullptr)
		return {};
	return [cb](int percent, const char* stage) { cb(percent, stage); };
}

QVariant vector(const std::vector<double>& values)
{
	Eigen::VectorXd v(Eigen::Index(values.size()));
	for (size_t i = 0; i < values.size(); ++i)
		v[Eigen::Index(i)] = values[i];
	return QVariant::fromValue(v);
}

std::map<std::string, QVariant> outputValues(const symmetry::DetectionResult& r, const symmetry::DetectionOptions& o,
                                             const std::vector<int>& layerIds)
{
	const int count = int(r.symmetries.size());
	const int loop = std::max(o.basis_loop_length, 1);
	std::vector<double> transforms, scales, reflections, rms, maxima, systematic, areas, supports, generators, words;
	std::vector<double> kinds, axes, pitches;
	for (const symmetry::DetectedSymmetry& s : r.symmetries) {
		const Eigen::Matrix4d m = s.transform.matrix();
		for (int i = 0; i < 4; ++i)
			for (int j = 0; j < 4; ++j)
				transforms.push_back(m(i, j));
		scales.push_back(s.transform.scale);
		reflections.push_back(s.transform.reflection ? 1 : 0);
		rms.push_back(s.rms_error);
		maxima.push_back(s.max_error);
		systematic.push_back(s.systematic_error);
		areas.push_back(s.source_area);
		supports.push_back(s.support);
		generators.push_back(s.is_generator ? 1 : 0);
		for (int i = 0; i < loop; ++i)
			words.push_back(i < int(s.word.size()) ? s.word[size_t(i)] : 0);
		kinds.push_back(int(s.continuous_kind));
		for (int i = 0; i < 3; ++i)
			axes.push_back(s.axis_point[i]);
		for (int i = 0; i < 3; ++i)
			axes.push_back(s.axis_direction[i]);
		pitches.push_back(s.pitch);
	}
	std::vector<double> layers(layerIds.begin(), layerIds.end());

	std::map<std::string, QVariant> out;
	out["symmetry_count"] = QVariant(count);
	out["transforms"] = vector(transforms);
	out["scales"] = vector(scales);
	out["is_reflection"] = vector(reflections);
	out["rms_errors"] = vector(rms);
	out["max_errors"] = vector(maxima);
	out["systematic_errors"] = vector(systematic);
	out["source_areas"] = vector(areas);
	out["supports"] = vector(supports);
	out["generator_count"] = QVariant(r.generator_count);
	out["is_generator"] = vector(generators);
	out["basis_words"] = vector(words);
	out["continuous_kinds"] = vector(kinds);
	out["continuous_axes"] = vector(axes);
	out["continuous_pitches"] = vector(pitches);
	out["patch_layer_ids"] = vector(layers);
	out["seconds_signatures"] = QVariant(r.seconds_signatures);
	out["seconds_pairing"] = QVariant(r.seconds_pairing);
	out["seconds_clustering"] = QVariant(r.seconds_clustering);
	out["seconds_verification"] = QVariant(r.seconds_verification);
	out["samples"] = QVariant(r.samples);
	out["pruned_samples"] = QVariant(r.pruned_samples);
	out["pairs"] = QVariant(r.pairs);
	out["clusters"] = QVariant(r.clusters);
	out["verified_clusters"] = QVariant(r.verified_candidates);
	out["working_vertices"] = QVariant(r.working_vertices);
	out["point_cloud"] = QVariant(r.point_cloud);
	out["normals_estimated"] = QVariant(r.normals_estimated);
	out["welded_vertices"] = QVariant(r.welded_vertices);
	out["flipped_faces"] = QVariant(r.flipped_faces);
	out["repeated_faces"] = QVariant(r.repeated_faces);
	out["back_faces"] = QVariant(r.back_faces);
	out["noise"] = QVariant(r.noise);
	out["smoothing_radius"] = QVariant(r.smoothing_radius);
	out["curvature_radius_used"] = QVariant(r.curvature_radius);
	out["pair_sample_count_used"] = QVariant(r.pairs_sample_count_used);
	return out;
}

}  // namespace

FilterSymmetryPlugin::FilterSymmetryPlugin()
{
	typeList = {FP_PARTIAL_SYMMETRIES, FP_SYMMETRIZATION, FP_REDUCTION, FP_EDITING, FP_SEGMENTATION};
	for (ActionIDType id : types())
		actionList.push_back(new QAction(filterName(id), this));
}

QString FilterSymmetryPlugin::pluginName() const
{
	return "FilterSymmetry";
}

QString FilterSymmetryPlugin::filterName(ActionIDType filter) const
{
	switch (filter) {
	case FP_PARTIAL_SYMMETRIES: return symmetry_texts::detectionName();
	case FP_SYMMETRIZATION: return symmetry_texts::symmetrizationName();
	case FP_REDUCTION: return symmetry_texts::reductionName();
	case FP_EDITING: return symmetry_texts::editingName();
	case FP_SEGMENTATION: return symmetry_texts::segmentationName();
	default: assert(0); return QString();
	}
}

QString FilterSymmetryPlugin::pythonFilterName(ActionIDType filter) const
{
	switch (filter) {
	case FP_PARTIAL_SYMMETRIES: return "compute_partial_symmetries";
	case FP_SYMMETRIZATION: return "apply_coord_symmetrization";
	case FP_REDUCTION: return "generate_symmetry_based_reduction";
	case FP_EDITING: return "apply_coord_consistent_editing";
	case FP_SEGMENTATION: return "compute_rigid_segments_between_meshes";
	default: assert(0); return QString();
	}
}

QString FilterSymmetryPlugin::filterInfo(ActionIDType filter) const
{
	switch (filter) {
	case FP_PARTIAL_SYMMETRIES: return symmetry_texts::detectionInfo(true);
	case FP_SYMMETRIZATION: return symmetry_texts::symmetrizationInfo(true);
	case FP_REDUCTION: return symmetry_texts::reductionInfo(true);
	case FP_EDITING: return symmetry_texts::editingInfo(true);
	case FP_SEGMENTATION: return symmetry_texts::segmentationInfo(true);
	default: assert(0); return QString();
	}
}

FilterPlugin::FilterClass FilterSymmetryPlugin::getClass(const QAction* action) const
{
	switch (ID(action)) {
	case FP_SYMMETRIZATION:
	case FP_EDITING: return FilterPlugin::Smoothing;
	case FP_REDUCTION: return FilterPlugin::Remeshing;
	default: return FilterPlugin::Measure;
	}
}

FilterPlugin::FilterArity FilterSymmetryPlugin::filterArity(const QAction* action) const
{
	return ID(action) == FP_SEGMENTATION ? FIXED : SINGLE_MESH;
}

int FilterSymmetryPlugin::getPreConditions(const QAction*) const
{
	// No MM_FACENUMBER: with it, MeshLab greys the entry out on a point cloud and pymeshlab
	// answers "Current mesh does not have Any Faces."  Detection runs on a point cloud; the
	// uses of a result (symmetrization, reduction, editing, segmentation) refuse one with a
	// sentence naming the reconstruction filters that make it a surface.
	return MeshModel::MM_NONE;
}

int FilterSymmetryPlugin::postCondition(const QAction* action) const
{
	return symmetry_host::changedData(filterOf(action));
}

RichParameterList FilterSymmetryPlugin::initParameterList(const QAction* action, const MeshDocument& md)
{
	RichParameterList parameters;
	symmetry_host::appendParameters(filterOf(action), md, parameters);
	return parameters;
}

symmetry_host::Filter FilterSymmetryPlugin::filterOf(const QAction* action) const
{
	switch (ID(action)) {
	case FP_PARTIAL_SYMMETRIES: return symmetry_host::Filter::Detection;
	case FP_SYMMETRIZATION: return symmetry_host::Filter::Symmetrization;
	case FP_REDUCTION: return symmetry_host::Filter::Reduction;
	case FP_EDITING: return symmetry_host::Filter::Editing;
	case FP_SEGMENTATION: return symmetry_host::Filter::Segmentation;
	default: wrongActionCalled(action);
	}
	return symmetry_host::Filter::Detection;
}

std::map<std::string, QVariant> FilterSymmetryPlugin::applyFilter(
	const QAction* action, const RichParameterList& parameters, MeshDocument& md, unsigned int& /*postConditionMask*/,
	vcg::CallBackPos* cb)
{
	switch (ID(action)) {
	case FP_PARTIAL_SYMMETRIES: return detectPartialSymmetries(md, parameters, cb);
	case FP_SYMMETRIZATION: return symmetrize(md, parameters, cb);
	case FP_REDUCTION: return reduce(md, parameters, cb);
	case FP_EDITING: return carryEdit(md, parameters, cb);
	case FP_SEGMENTATION: return segment(md, parameters, cb);
	default: wrongActionCalled(action);
	}
	return {};
}

std::map<std::string, QVariant> FilterSymmetryPlugin::detectPartialSymmetries(
	MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* input = md.mm();
	if (input == nullptr)
		throw MLException("There is no current mesh to detect symmetries on.");
	const Detection detection = symmetry_host::runDetection(input->cm, parameters, progressOf(cb), 100, true);
	// Detection succeeded: from here on the document is written.
	const std::vector<int> layerIds = symmetry_host::writeDetection(
		md, *input, detection, symmetry_parameters::createPatchLayers(parameters));
	for (const QString& line : symmetry_host::detectionLog(detection))
		log(line.toStdString());
	return outputValues(detection.result, detection.options, layerIds);
}

std::map<std::string, QVariant> FilterSymmetryPlugin::symmetrize(
	MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* input = md.mm();
	if (input == nullptr)
		throw MLException("There is no current mesh to symmetrize.");
	const symmetry_host::Symmetrization done = symmetry_host::symmetrizeMesh(input->cm, parameters, progressOf(cb));
	log(symmetry_host::symmetrizationLog(done).toStdString());
	std::map<std::string, QVariant> out;
	out["symmetry_count"] = QVariant(done.symmetryCount);
	out["symmetrized_vertices"] = QVariant(done.moved.moved_vertices);
	out["rms_before"] = QVariant(done.moved.rms_before);
	out["rms_after"] = QVariant(done.moved.rms_after);
	return out;
}

std::map<std::string, QVariant> FilterSymmetryPlugin::reduce(
	MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* input = md.mm();
	if (input == nullptr)
		throw MLException("There is no current mesh to reduce.");
	const symmetry_host::Reduction done = symmetry_host::reduceMesh(md, *input, parameters, progressOf(cb));
	log(symmetry_host::reductionLog(done).toStdString());
	const std::vector<int>& kept = done.reduced.kept_faces;
	std::vector<double> transforms, faceCounts, faces, removed;
	for (const symmetry::ReducedInstance& instance : done.reduced.instances) {
		const Eigen::Matrix4d m = instance.transform.matrix();
		for (int i = 0; i < 4; ++i)
			for (int j = 0; j < 4; ++j)
				transforms.push_back(m(i, j));
		faceCounts.push_back(double(instance.faces.size()));
		for (int f : instance.faces)
			faces.push_back(double(std::lower_bound(kept.begin(), kept.end(), f) - kept.begin()));
		removed.push_back(instance.removed_faces);
	}
	std::map<std::string, QVariant> out;
	out["symmetry_count"] = QVariant(done.symmetryCount);
	out["reduced_faces"] = QVariant(int(kept.size()));
	out["size_ratio"] = QVariant(done.reduced.size_ratio);
	out["instance_count"] = QVariant(int(done.reduced.instances.size()));
	out["instance_transforms"] = vector(transforms);
	out["instance_face_counts"] = vector(faceCounts);
	out["instance_faces"] = vector(faces);
	out["instance_removed_faces"] = vector(removed);
	out["reconstruction_error"] = QVariant(done.reduced.reconstruction_error);
	out["reduced_layer_id"] = QVariant(done.reducedLayerId);
	out["reconstruction_layer_id"] = QVariant(done.reconstructionLayerId);
	return out;
}

std::map<std::string, QVariant> FilterSymmetryPlugin::carryEdit(
	MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* edited = md.mm();
	MeshModel* original = symmetry_host::originalMesh(md, parameters);
	if (edited == nullptr || original == nullptr)
		throw MLException("Consistent editing needs the edited mesh as the current mesh and the original as original_mesh.");
	const symmetry_host::Editing done = symmetry_host::carryEdit(*original, *edited, parameters, progressOf(cb));
	log(symmetry_host::editingLog(done).toStdString());
	std::map<std::string, QVariant> out;
	out["symmetry_count"] = QVariant(done.symmetryCount);
	out["edited_vertices"] = QVariant(done.moved.edited_vertices);
	out["carried_vertices"] = QVariant(done.moved.carried_vertices);
	out["passes"] = QVariant(done.moved.passes);
	return out;
}

std::map<std::string, QVariant> FilterSymmetryPlugin::segment(
	MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	const symmetry_host::Segmentation done = symmetry_host::segmentPoses(md, parameters, progressOf(cb));
	for (const QString& line : symmetry_host::segmentationLog(done))
		log(line.toStdString());
	std::vector<double> transforms, firstCounts, secondCounts, errors, layerIds;
	double firstLabelled = 0, secondLabelled = 0;
	for (const symmetry::RigidSegment& segment : done.found.segments) {
		const Eigen::Matrix4d m = segment.transform.matrix();
		for (int i = 0; i < 4; ++i)
			for (int j = 0; j < 4; ++j)
				transforms.push_back(m(i, j));
		firstCounts.push_back(double(segment.first_vertices.size()));
		secondCounts.push_back(double(segment.second_vertices.size()));
		errors.push_back(segment.rms_error);
		firstLabelled += double(segment.first_vertices.size());
		secondLabelled += double(segment.second_vertices.size());
	}
	for (int id : done.layerIds)
		layerIds.push_back(double(id));
	std::map<std::string, QVariant> out;
	out["segment_count"] = QVariant(int(done.found.segments.size()));
	out["segment_transforms"] = vector(transforms);
	out["segment_first_vertex_counts"] = vector(firstCounts);
	out["segment_second_vertex_counts"] = vector(secondCounts);
	out["segment_rms_errors"] = vector(errors);
	out["first_labelled_share"] = QVariant(firstLabelled / std::max(1, done.firstRows));
	out["second_labelled_share"] = QVariant(secondLabelled / std::max(1, done.secondRows));
	out["segment_layer_ids"] = vector(layerIds);
	return out;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterSymmetryPlugin)
