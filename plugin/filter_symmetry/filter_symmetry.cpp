#include "filter_symmetry.h"

#include "symmetry_parameters.h"

#include <core/detection.h>
#include <core/symmetrization.h>

#include <common/mlexception.h>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// Name of the per-vertex attribute holding the symmetry index (public API).
const char* const kSymmetryIdAttribute = "symmetry_id";

/// The current mesh as the core sees it: non-deleted vertices and faces, compacted.
struct HostMesh {
	Eigen::MatrixX3d V;                  ///< #V by 3 positions
	Eigen::MatrixX3i F;                  ///< #F by 3 rows of V
	std::vector<CVertexO*> vertexOfRow;  ///< the CMeshO vertex behind each row of V
};

HostMesh copyMesh(CMeshO& m)
{
	HostMesh h;
	std::vector<int> rowOfVertex(m.vert.size(), -1);
	for (size_t i = 0; i < m.vert.size(); ++i) {
		if (!m.vert[i].IsD()) {
			rowOfVertex[i] = int(h.vertexOfRow.size());
			h.vertexOfRow.push_back(&m.vert[i]);
		}
	}
	h.V.resize(Eigen::Index(h.vertexOfRow.size()), 3);
	for (size_t r = 0; r < h.vertexOfRow.size(); ++r)
		for (int c = 0; c < 3; ++c)
			h.V(Eigen::Index(r), c) = double(h.vertexOfRow[r]->P()[c]);

	std::vector<Eigen::Vector3i> faces;
	faces.reserve(m.face.size());
	for (const CFaceO& f : m.face) {
		if (f.IsD())
			continue;
		Eigen::Vector3i row;
		bool valid = true;
		for (int c = 0; c < 3; ++c) {
			const CVertexO* v = f.cV(c);
			if (v == nullptr) {
				valid = false;
				break;
			}
			// A reader can leave a face pointing past the vertex array (MeshLab's OBJ reader
			// on out-of-range indices, assimp's invalid/malformed.obj): check the index
			// before touching the vertex, which is not there.
			if (v < m.vert.data() || v >= m.vert.data() + m.vert.size())
				throw symmetry::InputError(
					"The mesh has faces that refer to vertices that do not exist (the file is malformed: "
					"its face indices go past its vertex list); repair the file, or remove those faces in "
					"the program that wrote it.");
			if (v->IsD()) {
				valid = false;
				break;
			}
			row[c] = rowOfVertex[size_t(v - m.vert.data())];
		}
		if (valid)
			faces.push_back(row);
	}
	h.F.resize(Eigen::Index(faces.size()), 3);
	for (size_t i = 0; i < faces.size(); ++i)
		h.F.row(Eigen::Index(i)) = faces[i].transpose();
	return h;
}

/// A result that does not fit the input would corrupt the document: refuse it before
/// anything is written.  Throws std::logic_error (a bug in the core, not user error).
void checkResult(const symmetry::DetectionResult& r, Eigen::Index rows, const symmetry::DetectionOptions& o)
{
	auto fail = [](const std::string& what) { throw std::logic_error(what); };
	const int count = int(r.symmetries.size());
	if (Eigen::Index(r.vertex_deviation.size()) != rows || Eigen::Index(r.vertex_symmetry_id.size()) != rows)
		fail("per-vertex outputs do not match the vertex count");
	for (double d : r.vertex_deviation)
		if (!std::isfinite(d))
			fail("a vertex deviation is not a finite number");
	for (int id : r.vertex_symmetry_id)
		if (id < -1 || id >= count)
			fail("a vertex symmetry index is out of range");
	for (const symmetry::DetectedSymmetry& s : r.symmetries) {
		for (const std::vector<int>* patch : {&s.source_vertices, &s.target_vertices})
			for (int v : *patch)
				if (v < 0 || Eigen::Index(v) >= rows)
					fail("a patch vertex index is out of range");
		if (int(s.word.size()) > std::max(o.basis_loop_length, 1))
			fail("a basis word is longer than basis_loop_length");
	}
}

/// v.Q() = signed deviation (fraction of the diagonal); colour ramp over [-m, m],
/// grey where no symmetry holds.
void writeQualityAndColour(MeshModel& mm, const HostMesh& h, const symmetry::DetectionResult& r)
{
	mm.updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
	double range = 0;
	for (double d : r.vertex_deviation)
		range = std::max(range, std::abs(d));
	if (!(range > 0))
		range = 1e-6;  // all exact: the ramp's centre colour everywhere
	for (size_t row = 0; row < h.vertexOfRow.size(); ++row) {
		CVertexO& v = *h.vertexOfRow[row];
		v.Q() = Scalarm(r.vertex_deviation[row]);
		if (r.vertex_symmetry_id[row] < 0)
			v.C() = vcg::Color4b(vcg::Color4b::Gray);
		else
			v.C().SetColorRamp(float(-range), float(range), float(r.vertex_deviation[row]));
	}
}

/// Per-vertex Scalarm attribute `symmetry_id`, replacing one left by an earlier run
/// (whatever its type).  Deleted vertices get -1.
void writeSymmetryIdAttribute(CMeshO& m, const HostMesh& h, const symmetry::DetectionResult& r)
{
	if (vcg::tri::HasPerVertexAttribute(m, kSymmetryIdAttribute))
		vcg::tri::Allocator<CMeshO>::DeletePerVertexAttribute(m, kSymmetryIdAttribute);
	auto id = vcg::tri::Allocator<CMeshO>::AddPerVertexAttribute<Scalarm>(m, kSymmetryIdAttribute);
	for (CVertexO& v : m.vert)
		id[v] = Scalarm(-1);
	for (size_t row = 0; row < h.vertexOfRow.size(); ++row)
		id[*h.vertexOfRow[row]] = Scalarm(r.vertex_symmetry_id[row]);
}

/// Copies of the input vertices in `rows` (with position, normal, colour, quality) and
/// of the faces whose three vertices are all among them.
CMeshO patchMesh(const HostMesh& h, const std::vector<int>& rows)
{
	std::vector<int> patchIndex(size_t(h.V.rows()), -1);
	for (int row : rows)
		patchIndex[size_t(row)] = 0;
	int n = 0;
	for (int& i : patchIndex)
		if (i == 0)
			i = n++;

	CMeshO patch;
	vcg::tri::Allocator<CMeshO>::AddVertices(patch, size_t(n));
	for (size_t row = 0; row < patchIndex.size(); ++row) {
		if (patchIndex[row] < 0)
			continue;
		CVertexO& dst = patch.vert[size_t(patchIndex[row])];
		const CVertexO& src = *h.vertexOfRow[row];
		dst.P() = src.cP();
		dst.N() = src.cN();
		dst.C() = src.cC();
		dst.Q() = src.cQ();
	}

	std::vector<Eigen::Vector3i> faces;
	for (Eigen::Index f = 0; f < h.F.rows(); ++f) {
		Eigen::Vector3i t(patchIndex[size_t(h.F(f, 0))], patchIndex[size_t(h.F(f, 1))],
		                  patchIndex[size_t(h.F(f, 2))]);
		if (t.minCoeff() >= 0)
			faces.push_back(t);
	}
	if (!faces.empty()) {
		auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(patch, faces.size());
		for (size_t i = 0; i < faces.size(); ++i, ++fi)
			for (int c = 0; c < 3; ++c)
				fi->V(c) = &patch.vert[size_t(faces[i][c])];
	}
	return patch;
}

// What a reported symmetry is, in words: a continuous family with its axis, or the kind of
// the discrete transformation (a rotation whose axis it also slides along is a screw, a
// mirror that also slides along its plane a glide reflection, a mirror composed with a turn
// about its normal a rotoreflection).  `diagonal` sets the
// lengths below which a slide is none.
QString kindLabel(const symmetry::DetectedSymmetry& s, double diagonal)
{
	using symmetry::ContinuousKind;
	const Eigen::Vector3d& p = s.axis_point;
	const Eigen::Vector3d& d = s.axis_direction;
	const QString axis = QString("point (%1, %2, %3), direction (%4, %5, %6)")
		.arg(p.x(), 0, 'g', 4).arg(p.y(), 0, 'g', 4).arg(p.z(), 0, 'g', 4)
		.arg(d.x(), 0, 'f', 3).arg(d.y(), 0, 'f', 3).arg(d.z(), 0, 'f', 3);
	switch (s.continuous_kind) {
	case ContinuousKind::Rotational: return "rotational family about the axis " + axis;
	case ContinuousKind::Translational: return QString("translational family along (%1, %2, %3)")
		.arg(d.x(), 0, 'f', 3).arg(d.y(), 0, 'f', 3).arg(d.z(), 0, 'f', 3);
	case ContinuousKind::Helical: return QString("helical family about the axis %1, pitch %2% of the diagonal")
		.arg(axis).arg(100 * s.pitch, 0, 'g', 3);
	case ContinuousKind::Planar: return "planar family, plane through " + QString(axis).replace("direction", "normal");
	case ContinuousKind::Spherical: return QString("spherical family, centre (%1, %2, %3)")
		.arg(p.x(), 0, 'g', 4).arg(p.y(), 0, 'g', 4).arg(p.z(), 0, 'g', 4);
	case ContinuousKind::Discrete: break;
	}
	const symmetry::Transformation& t = s.transform;
	const double slide_floor = 1e-3 * diagonal;
	if (std::abs(t.scale - 1) > 1e-6)
		return QString("similarity (scale %1)").arg(t.scale, 0, 'g', 4);
	const Eigen::Matrix3d L = t.linear();
	if (t.reflection) {
		// The mirror's normal n: L n = -n.  A glide slides along the plane: (t - (t.n) n).
		Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e(0.5 * (L + L.transpose()));
		const Eigen::Vector3d n = e.eigenvectors().col(0);
		const Eigen::Vector3d slide = t.translation - n * n.dot(t.translation);
		if ((L * L - Eigen::Matrix3d::Identity()).norm() >= 1e-3) {
			// Not an involution: a mirror composed with a turn about its normal.  -L is a
			// proper rotation by 180 degrees plus that turn.
			const double turn = 180 - Eigen::AngleAxisd(Eigen::Matrix3d(-L)).angle() * 180 / M_PI;
			return QString("rotoreflection (mirror and turn by %1 degrees)").arg(std::abs(turn), 0, 'f', 1);
		}
		return slide.norm() > slide_floor ? "glide reflection" : "reflection";
	}
	if ((L - Eigen::Matrix3d::Identity()).norm() < 1e-6)
		return "translation";
	const Eigen::AngleAxisd r(L);
	const double angle = r.angle() * 180 / M_PI;
	const double slide = std::abs(r.axis().dot(t.translation));
	return QString("%1 by %2 degrees").arg(slide > slide_floor ? "screw" : "rotation").arg(angle, 0, 'f', 1);
}

QString wordText(const symmetry::Word& word)
{
	QStringList letters;
	for (int letter : word)
		letters << QString("%1g%2").arg(letter < 0 ? "-" : "+").arg(std::abs(letter) - 1);
	return letters.isEmpty() ? QString("identity") : letters.join(" ");
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
	out["welded_vertices"] = QVariant(r.welded_vertices);
	out["flipped_faces"] = QVariant(r.flipped_faces);
	out["noise"] = QVariant(r.noise);
	out["smoothing_radius"] = QVariant(r.smoothing_radius);
	out["curvature_radius_used"] = QVariant(r.curvature_radius);
	out["pair_sample_count_used"] = QVariant(r.pairs_sample_count_used);
	return out;
}

/// Calls `work` (the core), turning every failure into an MLException whose sentence starts
/// with `task` and says that the mesh was left unchanged: nothing is written before it returns.
template <class Work>
void callCore(const QString& task, Work&& work)
{
	try {
		work();
	}
	catch (const symmetry::InputError& e) {
		throw MLException(QString::fromStdString(e.what()));
	}
	catch (const MLException&) {
		throw;
	}
	catch (const std::bad_alloc&) {
		throw MLException(task + " ran out of memory. The mesh was left unchanged; try fewer samples "
		                         "(sample_count, pair_sample_count).");
	}
	catch (const std::exception& e) {
		throw MLException(task + QString(" failed because of an internal error (%1). The mesh was left unchanged; "
		                                 "please report this with the mesh and the parameters used.")
		                             .arg(QString::fromLocal8Bit(e.what())));
	}
	catch (...) {
		throw MLException(task + " failed because of an unknown internal error. The mesh was left unchanged; "
		                         "please report this with the mesh and the parameters used.");
	}
}

/// What detection found on the current mesh, with the mesh and options it ran on.
struct Detection {
	HostMesh host;
	symmetry::DetectionOptions options;
	symmetry::DetectionResult result;
};

/// Runs the core's detection on `m` with the filter's parameters; the progress bar goes
/// from 0 to `progressEnd` percent.  Writes nothing.
Detection runDetection(CMeshO& m, const RichParameterList& parameters, vcg::CallBackPos* cb, int progressEnd)
{
	Detection d;
	callCore("Symmetry detection", [&] {
		// The host turned the percentages into lengths with this diagonal; undo it the same way.
		const double diagonal = m.bbox.IsNull() ? 0.0 : double(m.bbox.Diag());
		d.options = symmetry_parameters::fromRichParameterList(parameters, diagonal);
		d.options.validate();
		d.host = copyMesh(m);
		// The core reports on this thread only, so forwarding to MeshLab's callback is safe.
		symmetry::Progress progress = [cb, progressEnd](int percent, const char* stage) {
			if (cb != nullptr)
				cb(std::clamp(percent, 0, 100) * progressEnd / 100, stage);
		};
		d.result = symmetry::detect_partial_symmetries(d.host.V, d.host.F, d.options, progress);
		checkResult(d.result, d.host.V.rows(), d.options);
	});
	return d;
}

}  // namespace

FilterSymmetryPlugin::FilterSymmetryPlugin()
{
	typeList = {FP_PARTIAL_SYMMETRIES, FP_SYMMETRIZATION};
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
	case FP_PARTIAL_SYMMETRIES: return "Detect Partial and Approximate Symmetries";
	case FP_SYMMETRIZATION: return "Symmetrize Approximate Symmetries";
	default: assert(0); return QString();
	}
}

QString FilterSymmetryPlugin::pythonFilterName(ActionIDType filter) const
{
	switch (filter) {
	case FP_PARTIAL_SYMMETRIES: return "compute_partial_symmetries";
	case FP_SYMMETRIZATION: return "apply_coord_symmetrization";
	default: assert(0); return QString();
	}
}

QString FilterSymmetryPlugin::filterInfo(ActionIDType filter) const
{
	switch (filter) {
	case FP_PARTIAL_SYMMETRIES:
		return "Finds parts of the surface that are mapped onto other parts by a rotation, reflection, "
		       "translation or uniform scaling, even when the symmetry is only partial (it holds on some "
		       "patches, not on the whole model) and approximate (it holds up to a tolerance).<br>"
		       "Curvature signatures are computed at surface samples; pairs of similar samples vote for the "
		       "transformation that maps one onto the other; mean-shift clustering of the votes in "
		       "transformation space gives candidate symmetries, each verified by growing the pair of patches "
		       "it maps onto each other; finally the symmetries are reduced to a few generators.<br><br>"
		       "<b>Outputs</b><br>"
		       "<i>Vertex quality</i>: signed deviation from perfect symmetry of each vertex under the most "
		       "significant symmetry it belongs to, as a fraction of the bounding-box diagonal (Figure 1 of "
		       "the paper); 0 where no symmetry holds.<br>"
		       "<i>Vertex colour</i>: a ramp over that deviation, symmetric around 0; grey where no symmetry "
		       "holds.<br>"
		       "<i>Attribute symmetry_id</i> (per vertex, scalar): index of that symmetry, -1 where none "
		       "holds.<br>"
		       "<i>Layers symmetry_k_source and symmetry_k_target</i> (if <i>Create patch layers</i> is on): "
		       "the two patches that symmetry k maps onto each other; the input stays the current mesh.<br>"
		       "<i>Returned values</i>: symmetry_count; transforms (16 numbers per symmetry, the row-major 4x4 "
		       "matrix mapping the source patch onto the target; for a continuous family one of its members); "
		       "scales, is_reflection, rms_errors and max_errors (deviation from perfect symmetry, fraction of "
		       "the diagonal), systematic_errors (the deviation averaged over neighbourhoods, what noise leaves), "
		       "source_areas (fraction of the total area) and supports (votes for it), one per symmetry; "
		       "continuous_kinds (0 discrete, 1 rotational, 2 translational, 3 helical, 4 planar, 5 spherical), "
		       "continuous_axes (6 per symmetry: a point on the axis, plane or the centre, then the unit axis, "
		       "normal or direction; zeros for a discrete symmetry) and continuous_pitches (helical: advance per "
		       "turn, fraction of the diagonal); generator_count, is_generator and basis_words "
		       "(basis_loop_length letters per symmetry, padded with 0: letter +k is generator k-1, -k its "
		       "inverse; continuous families are not in the basis); patch_layer_ids (source and target layer id "
		       "per symmetry, -1 without layers); stage times seconds_signatures, seconds_pairing, "
		       "seconds_clustering, seconds_verification; work counts samples, pruned_samples, pairs, clusters, "
		       "verified_clusters; and what the filter chose from the mesh: working_vertices (vertices of the "
		       "simplified copy analysed, 0 when the mesh itself was), welded_vertices (vertices of a "
		       "triangle soup at the same position as another, welded on the filter's copy), flipped_faces (faces "
		       "turned on that copy to orient each part coherently and outward), noise (estimated, fraction of the "
		       "diagonal), smoothing_radius (presmoothing of a noisy mesh, 0 if none), curvature_radius_used and "
		       "pair_sample_count_used.<br><br>"
		       "See:<br><i>Niloy J. Mitra, Leonidas J. Guibas, Mark Pauly</i><br>"
		       "<b>\"Partial and Approximate Symmetry Detection for 3D Geometry\"</b><br>"
		       "ACM Transactions on Graphics 25(3) (SIGGRAPH 2006), pages 560-568.";
	case FP_SYMMETRIZATION:
		return "Detects the partial and approximate symmetries of the current mesh (with the parameters of "
		       "<i>Detect Partial and Approximate Symmetries</i>), then moves the vertices of each approximately "
		       "symmetric pair of patches towards their exactly symmetric average: a vertex whose image under the "
		       "symmetry lands off the surface moves so that its image goes half-way (times <i>Strength</i>) to the "
		       "surface, and the other side moves by the same rule under the inverse, so both meet in the middle; "
		       "<i>Iterations</i> passes, each on the surface the previous one left. A vertex moves under the most "
		       "significant symmetry it is in; vertices in no symmetry, and on continuous families (which have "
		       "no single transformation), do not move. An exactly symmetric pair does not move.<br>"
		       "<i>Returned values</i>: symmetry_count (symmetries detected), symmetrized_vertices (vertices "
		       "moved), rms_before and rms_after (RMS deviation from perfect symmetry of those vertices, fraction "
		       "of the diagonal, before and after).<br>"
		       "Symmetrization is named as future work in: <i>Niloy J. Mitra, Leonidas J. Guibas, Mark Pauly</i>, "
		       "<b>\"Partial and Approximate Symmetry Detection for 3D Geometry\"</b>, SIGGRAPH 2006; see also "
		       "Mitra, Guibas, Pauly, \"Symmetrization\", SIGGRAPH 2007.";
	default: assert(0); return QString();
	}
}

FilterPlugin::FilterClass FilterSymmetryPlugin::getClass(const QAction* action) const
{
	return ID(action) == FP_SYMMETRIZATION ? FilterPlugin::Smoothing : FilterPlugin::Measure;
}

FilterPlugin::FilterArity FilterSymmetryPlugin::filterArity(const QAction*) const
{
	return SINGLE_MESH;
}

int FilterSymmetryPlugin::getPreConditions(const QAction*) const
{
	// No MM_FACENUMBER: with it, MeshLab greys the entry out on a point cloud and pymeshlab
	// answers "Current mesh does not have Any Faces."; without it, the core refuses a point
	// cloud with a sentence naming the reconstruction filters that make it a surface.
	return MeshModel::MM_NONE;
}

int FilterSymmetryPlugin::postCondition(const QAction* action) const
{
	if (ID(action) == FP_SYMMETRIZATION)
		return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL;
	return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
}

RichParameterList FilterSymmetryPlugin::initParameterList(const QAction* action, const MeshModel& m)
{
	RichParameterList parameters;
	switch (ID(action)) {
	case FP_PARTIAL_SYMMETRIES:
		symmetry_parameters::toRichParameterList(symmetry::DetectionOptions(), m.cm.bbox.Diag(), true, parameters);
		break;
	case FP_SYMMETRIZATION:
		symmetry_parameters::toRichParameterList(symmetry::DetectionOptions(), m.cm.bbox.Diag(), std::nullopt, parameters);
		symmetry_parameters::appendSymmetrizationParameters(symmetry::SymmetrizationOptions(), parameters);
		break;
	default: wrongActionCalled(action);
	}
	return parameters;
}

std::map<std::string, QVariant> FilterSymmetryPlugin::applyFilter(
	const QAction* action, const RichParameterList& parameters, MeshDocument& md, unsigned int& /*postConditionMask*/,
	vcg::CallBackPos* cb)
{
	switch (ID(action)) {
	case FP_PARTIAL_SYMMETRIES: return detectPartialSymmetries(md, parameters, cb);
	case FP_SYMMETRIZATION: return symmetrize(md, parameters, cb);
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
	CMeshO& m = input->cm;

	Detection detection = runDetection(m, parameters, cb, 100);
	const HostMesh& host = detection.host;
	const symmetry::DetectionOptions& options = detection.options;
	const symmetry::DetectionResult& result = detection.result;

	// Detection succeeded: from here on the document is written.
	std::vector<int> layerIds(2 * result.symmetries.size(), -1);
	try {
		writeQualityAndColour(*input, host, result);
		writeSymmetryIdAttribute(m, host, result);
		if (symmetry_parameters::createPatchLayers(parameters)) {
			const int inputId = int(input->id());
			for (size_t k = 0; k < result.symmetries.size(); ++k) {
				const symmetry::DetectedSymmetry& s = result.symmetries[k];
				const QString name = QString("symmetry_%1_").arg(k);
				layerIds[2 * k] = int(md.addNewMesh(patchMesh(host, s.source_vertices), name + "source", false)->id());
				layerIds[2 * k + 1] =
					int(md.addNewMesh(patchMesh(host, s.target_vertices), name + "target", false)->id());
			}
			md.setCurrentMesh(inputId);
		}
	}
	catch (const std::bad_alloc&) {
		throw MLException("Symmetry detection ran out of memory while writing its results.");
	}

	for (size_t k = 0; k < result.symmetries.size(); ++k) {
		const symmetry::DetectedSymmetry& s = result.symmetries[k];
		const QString basis = s.continuous_kind != symmetry::ContinuousKind::Discrete
		                          ? QString("continuous")
		                          : QString("%1 (%2)").arg(s.is_generator ? "generator" : "compound").arg(wordText(s.word));
		log("Symmetry %d: %s; %d -> %d vertices, source area %.3g%%, deviation rms %.3g%% max %.3g%% of the "
		    "diagonal, support %d, %s",
		    int(k), qUtf8Printable(kindLabel(s, host.V.rows() ? (host.V.colwise().maxCoeff() - host.V.colwise().minCoeff()).norm() : 1.0)),
		    int(s.source_vertices.size()), int(s.target_vertices.size()), 100 * s.source_area, 100 * s.rms_error,
		    100 * s.max_error, s.support, qUtf8Printable(basis));
	}
	if (result.welded_vertices > 0)
		log("The mesh is a triangle soup (most triangles have vertices of their own): the filter welded %d "
		    "vertices lying at the same position as another on its own copy, the mesh is unchanged (Cleaning "
		    "and Repairing > Remove Duplicate Vertices welds them in the mesh itself).",
		    result.welded_vertices);
	if (result.flipped_faces > 0)
		log("%d faces were turned against the others around them or inward: the filter oriented each part "
		    "coherently, closed ones outward, on its own copy, the mesh is unchanged (Normals, Curvatures and "
		    "Orientation > Re-Orient all faces coherently does this to the mesh itself).",
		    result.flipped_faces);
	if (!result.orientable)
		log("The mesh is not orientable (a Moebius band, or faces folded through non-manifold edges): it was "
		    "analysed with its faces as they are, and symmetries where the orientation changes may be missed.");
	if (result.working_vertices > 0)
		log("The mesh has %d vertices, more than the working resolution (max_working_vertices = %d): it was "
		    "analysed on a copy simplified to %d vertices, and the patches and deviations are those of the mesh "
		    "itself.",
		    int(host.V.rows()), options.working.max_vertices, result.working_vertices);
	if (result.pair_sample_count_automatic) {
		const symmetry::SampleSize& n = result.pair_sample_size;
		log("Paired samples: n' = %d of %d. The Appendix's bound (Equation 1) for patches of %.3g%% of the samples "
		    "found with probability %.3g%% (mu = %.1f points in transformation space per paired sample) %s.",
		    result.pairs_sample_count_used, result.pruned_samples, 100 * n.p, 100 * (1 - n.alpha),
		    result.partners_per_sample,
		    qUtf8Printable(n.bound_met ? QString("asks for n' = %1").arg(n.n_prime)
		                               : QString("is not met even by pairing every sample; more samples "
		                                         "(sample_count) would meet it")));
		if (result.rigid_pair_sample_count > 0 && result.rigid_pair_sample_count <= result.pairs_sample_count_used)
			log("A restricted group pairs no more samples than rotations and reflections would (n' = %d): its "
			    "votes are those of the full group's pairs that are of its kind.",
			    result.rigid_pair_sample_count);
	}
	log("%d symmetries (%d generators) from %d samples (%d after pruning), %d pairs, %d clusters; "
	    "%.2f s signatures, %.2f s pairing, %.2f s clustering, %.2f s verification",
	    int(result.symmetries.size()), result.generator_count, result.samples, result.pruned_samples, result.pairs,
	    result.clusters, result.seconds_signatures, result.seconds_pairing, result.seconds_clustering,
	    result.seconds_verification);

	return outputValues(result, options, layerIds);
}

std::map<std::string, QVariant> FilterSymmetryPlugin::symmetrize(
	MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* input = md.mm();
	if (input == nullptr)
		throw MLException("There is no current mesh to symmetrize.");
	CMeshO& m = input->cm;
	// Its own parameters first: a wrong strength is said before minutes of detection.
	const symmetry::SymmetrizationOptions options = symmetry_parameters::symmetrizationOptions(parameters);
	callCore("Symmetrization", [&] { options.validate(); });
	const Detection detection = runDetection(m, parameters, cb, 80);
	symmetry::SymmetrizationResult moved;
	callCore("Symmetrization", [&] {
		if (cb != nullptr)
			cb(80, "Symmetrization");
		moved = symmetry::symmetrize(detection.host.V, detection.host.F, detection.result,
		                             detection.options.verification_tolerance, options);
	});

	// Symmetrization succeeded: from here on the mesh is written.
	const HostMesh& host = detection.host;
	for (Eigen::Index row = 0; row < host.V.rows(); ++row)
		if (moved.V.row(row) != host.V.row(row))
			host.vertexOfRow[size_t(row)]->P() =
				Point3m(Scalarm(moved.V(row, 0)), Scalarm(moved.V(row, 1)), Scalarm(moved.V(row, 2)));
	vcg::tri::UpdateNormal<CMeshO>::PerVertexNormalizedPerFaceNormalized(m);
	vcg::tri::UpdateBounding<CMeshO>::Box(m);
	log("Symmetrized %d vertices under %d symmetries: RMS deviation from perfect symmetry %.3g%% -> %.3g%% of the "
	    "diagonal (strength %.2f, %d passes).",
	    moved.moved_vertices, int(detection.result.symmetries.size()), 100 * moved.rms_before, 100 * moved.rms_after,
	    options.strength, options.iterations);
	std::map<std::string, QVariant> out;
	out["symmetry_count"] = QVariant(int(detection.result.symmetries.size()));
	out["symmetrized_vertices"] = QVariant(moved.moved_vertices);
	out["rms_before"] = QVariant(moved.rms_before);
	out["rms_after"] = QVariant(moved.rms_after);
	return out;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterSymmetryPlugin)
