#include "host_mesh.h"

#include "symmetry_parameters.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>

#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

namespace symmetry_host {

namespace {

// Name of the per-vertex attribute holding the symmetry index (public API).
const char* const kSymmetryIdAttribute = "symmetry_id";

/// Per-vertex Scalarm attribute `name` holding idOfRow (per row of h.V), replacing one left
/// by an earlier run (whatever its type).  Deleted vertices get -1.
void writeVertexIdAttribute(CMeshO& m, const HostMesh& h, const std::vector<int>& idOfRow, const char* name)
{
	if (vcg::tri::HasPerVertexAttribute(m, name))
		vcg::tri::Allocator<CMeshO>::DeletePerVertexAttribute(m, name);
	auto id = vcg::tri::Allocator<CMeshO>::AddPerVertexAttribute<Scalarm>(m, name);
	for (CVertexO& v : m.vert)
		id[v] = Scalarm(-1);
	for (size_t row = 0; row < h.vertexOfRow.size(); ++row)
		id[*h.vertexOfRow[row]] = Scalarm(idOfRow[row]);
}

/// Copies of the input vertices in `rows` (with position, normal, colour, quality) and
/// of the faces whose three vertices are all among them, or, if `faceRows` is given, of
/// those faces (rows of h.F whose vertices are all in `rows`) alone.
void copyPatch(const HostMesh& h, const std::vector<int>& rows, CMeshO& patch,
               const std::vector<int>* faceRows = nullptr)
{
	std::vector<int> patchIndex(size_t(h.V.rows()), -1);
	for (int row : rows)
		patchIndex[size_t(row)] = 0;
	int n = 0;
	for (int& i : patchIndex)
		if (i == 0)
			i = n++;

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
	auto copyFace = [&](Eigen::Index f) {
		Eigen::Vector3i t(patchIndex[size_t(h.F(f, 0))], patchIndex[size_t(h.F(f, 1))],
		                  patchIndex[size_t(h.F(f, 2))]);
		if (t.minCoeff() >= 0)
			faces.push_back(t);
	};
	if (faceRows != nullptr)
		for (int f : *faceRows)
			copyFace(f);
	else
		for (Eigen::Index f = 0; f < h.F.rows(); ++f)
			copyFace(f);
	if (!faces.empty()) {
		auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(patch, faces.size());
		for (size_t i = 0; i < faces.size(); ++i, ++fi)
			for (int c = 0; c < 3; ++c)
				fi->V(c) = &patch.vert[size_t(faces[i][c])];
	}
}

// ", transform [r00 r01 r02 t0; r10 r11 r12 t1; r20 r21 r22 t2]": the 3 x 4 matrix that maps
// the source patch onto the target, for a log a script can read; empty for a continuous
// family, which its axis describes.
QString transformText(const symmetry::DetectedSymmetry& s)
{
	if (s.continuous_kind != symmetry::ContinuousKind::Discrete)
		return QString();
	const Eigen::Matrix4d m = s.transform.matrix();
	QStringList rows;
	for (int i = 0; i < 3; ++i)
		rows << QString::asprintf("%.6g %.6g %.6g %.6g", m(i, 0), m(i, 1), m(i, 2), m(i, 3));
	return ", transform [" + rows.join("; ") + "]";
}

}  // namespace

int changedData(Filter filter)
{
	if (filter == Filter::Symmetrization || filter == Filter::Editing)
		return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL;
	// Reduction adds layers and changes nothing of the input; as for detection, the numbers
	// keep the GUI from offering a preview.
	if (filter == Filter::Reduction)
		return MeshModel::MM_VERTNUMBER | MeshModel::MM_FACENUMBER;
	if (filter == Filter::Segmentation)
		return MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTNUMBER | MeshModel::MM_FACENUMBER;
	// Detection also adds the patch layers, meshes of their own: saying so (vertex and face
	// numbers) keeps the GUI from offering a preview, which would run the detection again
	// and add another set of layers at every change of a parameter.
	return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTNUMBER | MeshModel::MM_FACENUMBER;
}

void appendParameters(Filter filter, double diagonal, RichParameterList& parameters)
{
	if (filter == Filter::Detection) {
		symmetry_parameters::toRichParameterList(symmetry::DetectionOptions(), diagonal, true, parameters);
		return;
	}
	if (filter == Filter::Segmentation) {
		symmetry_parameters::toRichParameterList(symmetry::DetectionOptions(), diagonal, std::nullopt, parameters,
		                                         false);
		symmetry_parameters::appendSegmentationParameters(parameters);
		return;
	}
	symmetry_parameters::toRichParameterList(symmetry::DetectionOptions(), diagonal, std::nullopt, parameters);
	if (filter == Filter::Symmetrization)
		symmetry_parameters::appendSymmetrizationParameters(symmetry::SymmetrizationOptions(), parameters);
	else if (filter == Filter::Reduction)
		symmetry_parameters::appendReductionParameters(parameters);
}

namespace {

// The first mesh of the document other than `mesh`, or `mesh` if it is alone: the default
// of a second mesh parameter, as a boolean's second operand.
const MeshModel* anotherMesh(ParameterDocument md, const MeshModel* mesh)
{
#ifdef SYMMETRY_MESHLAB_2020_09
	for (const MeshModel* m : md.meshList)
		if (m != mesh)
			return m;
#else
	for (const MeshModel& m : md.meshIterator())
		if (&m != mesh)
			return &m;
#endif
	return mesh;
}

void addMeshParameter(ParameterDocument md, const MeshModel* mesh, const QString& name, const QString& label,
                      const QString& help, RichParameterList& parameters)
{
#ifdef SYMMETRY_MESHLAB_2020_09
	parameters.addParam(RichMesh(name, const_cast<MeshModel*>(mesh), &md, label, help));
#else
	parameters.addParam(RichMesh(name, mesh != nullptr ? mesh->id() : 0, &md, label, help));
#endif
}

// The mesh a mesh parameter names.
MeshModel* meshParameter(MeshDocument& md, const RichParameterList& parameters, const QString& name)
{
#ifdef SYMMETRY_MESHLAB_2020_09
	return parameters.getMesh(name);
#else
	return md.getMesh(parameters.getMeshId(name));
#endif
}

}  // namespace

void appendParameters(Filter filter, ParameterDocument md, RichParameterList& parameters)
{
	const MeshModel* current = md.mm();
	const double diagonal = current != nullptr ? double(current->cm.bbox.Diag()) : 0.0;
	if (filter == Filter::Segmentation) {
		addMeshParameter(md, current, "first_mesh", "First pose",
		                 "The shape in one pose. Lengths below are in its units (percentages of its diagonal).",
		                 parameters);
		addMeshParameter(md, anotherMesh(md, current), "second_mesh", "Second pose",
		                 "The same shape in another pose: its parts moved rigidly, tessellated alike or not.",
		                 parameters);
	}
	appendParameters(filter, diagonal, parameters);
	if (filter == Filter::Editing)
		addMeshParameter(md, anotherMesh(md, current), "original_mesh", "Original mesh",
		                 "The mesh before the edit (the symmetries are detected on it): the current mesh is its "
		                 "edited copy, with the same vertices and faces, some of them moved.",
		                 parameters);
}

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
	writeVertexIdAttribute(m, h, r.vertex_symmetry_id, kSymmetryIdAttribute);
}

namespace {

void finishLayer(MeshModel* layer)
{
#ifdef SYMMETRY_MESHLAB_2020_09
	layer->UpdateBoxAndNormals();
#else
	layer->updateBoxAndNormals();
	layer->updateDataMask();
#endif
}

}  // namespace

MeshModel* addPatchLayer(MeshDocument& md, const HostMesh& h, const std::vector<int>& rows, const QString& name)
{
	MeshModel* layer = md.addNewMesh(QString(), name, false);
	copyPatch(h, rows, layer->cm);
	finishLayer(layer);
	return layer;
}

MeshModel* addFaceLayer(MeshDocument& md, const HostMesh& h, const std::vector<int>& faceRows, const QString& name,
                        bool makeCurrent)
{
	std::vector<int> rows;
	for (int f : faceRows)
		for (int c = 0; c < 3; ++c)
			rows.push_back(h.F(f, c));
	std::sort(rows.begin(), rows.end());
	rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
	MeshModel* layer = md.addNewMesh(QString(), name, makeCurrent);
	copyPatch(h, rows, layer->cm, &faceRows);
	finishLayer(layer);
	return layer;
}

MeshModel* addMeshLayer(MeshDocument& md, const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const QString& name)
{
	MeshModel* layer = md.addNewMesh(QString(), name, false);
	auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(layer->cm, size_t(V.rows()));
	for (Eigen::Index v = 0; v < V.rows(); ++v, ++vi)
		vi->P() = Point3m(Scalarm(V(v, 0)), Scalarm(V(v, 1)), Scalarm(V(v, 2)));
	if (F.rows() > 0) {
		auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(layer->cm, size_t(F.rows()));
		for (Eigen::Index f = 0; f < F.rows(); ++f, ++fi)
			for (int c = 0; c < 3; ++c)
				fi->V(c) = &layer->cm.vert[size_t(F(f, c))];
	}
	finishLayer(layer);
	return layer;
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

namespace {

/// The normals of a point cloud's rows, or no rows when some vertex has none (zero or not
/// finite): the core then estimates them all.
Eigen::MatrixX3d cloudNormals(const HostMesh& h)
{
	Eigen::MatrixX3d N(Eigen::Index(h.vertexOfRow.size()), 3);
	for (size_t r = 0; r < h.vertexOfRow.size(); ++r) {
		const auto& n = h.vertexOfRow[r]->cN();
		N.row(Eigen::Index(r)) << double(n[0]), double(n[1]), double(n[2]);
		if (!N.row(Eigen::Index(r)).allFinite() || !(N.row(Eigen::Index(r)).norm() > 0))
			return Eigen::MatrixX3d(0, 3);
	}
	return N;
}

}  // namespace

Detection runDetection(CMeshO& m, const RichParameterList& parameters, const symmetry::Progress& report,
                       int progressEnd, bool pointCloudAllowed)
{
	Detection d;
	callCore("Symmetry detection", [&] {
		// The host turned the percentages into lengths with this diagonal; undo it the same way.
		const double diagonal = m.bbox.IsNull() ? 0.0 : double(m.bbox.Diag());
		d.options = symmetry_parameters::fromRichParameterList(parameters, diagonal);
		d.options.validate();
		d.host = copyMesh(m);
		// The core reports on this thread only, so forwarding to MeshLab's callback is safe.
		symmetry::Progress progress = [&report, progressEnd](int percent, const char* stage) {
			if (report)
				report(std::clamp(percent, 0, 100) * progressEnd / 100, stage);
		};
		if (pointCloudAllowed && d.host.F.rows() == 0 && d.host.V.rows() > 0)
			d.result = symmetry::detect_partial_symmetries_in_point_cloud(d.host.V, cloudNormals(d.host), d.options,
			                                                              progress);
		else
			d.result = symmetry::detect_partial_symmetries(d.host.V, d.host.F, d.options, progress);
		checkResult(d.result, d.host.V.rows(), d.options);
	});
	return d;
}


std::vector<int> writeDetection(MeshDocument& md, MeshModel& input, const Detection& d, bool createLayers)
{
	const HostMesh& host = d.host;
	const symmetry::DetectionResult& result = d.result;
	std::vector<int> layerIds(2 * result.symmetries.size(), -1);
	try {
		writeQualityAndColour(input, host, result);
		writeSymmetryIdAttribute(input.cm, host, result);
		if (createLayers) {
			for (size_t k = 0; k < result.symmetries.size(); ++k) {
				const symmetry::DetectedSymmetry& s = result.symmetries[k];
				const QString name = QString("symmetry_%1_").arg(k);
				layerIds[2 * k] = int(addPatchLayer(md, host, s.source_vertices, name + "source")->id());
				layerIds[2 * k + 1] = int(addPatchLayer(md, host, s.target_vertices, name + "target")->id());
			}
			// The layers were added without becoming current.  Setting the current mesh again
			// anyway would be harmful: in the GUI it signals a change of current mesh, on which
			// the filter's dialog puts back the state the mesh had before the filter (its
			// colours and quality), as it does when the user picks another layer.
			if (md.mm() != &input)
				md.setCurrentMesh(int(input.id()));
		}
	}
	catch (const std::bad_alloc&) {
		throw MLException("Symmetry detection ran out of memory while writing its results.");
	}
	return layerIds;
}

QStringList detectionLog(const Detection& d)
{
	const HostMesh& host = d.host;
	const symmetry::DetectionOptions& options = d.options;
	const symmetry::DetectionResult& result = d.result;
	QStringList lines;
	const double diagonal =
		host.V.rows() ? (host.V.colwise().maxCoeff() - host.V.colwise().minCoeff()).norm() : 1.0;
	for (size_t k = 0; k < result.symmetries.size(); ++k) {
		const symmetry::DetectedSymmetry& s = result.symmetries[k];
		const QString basis = s.continuous_kind != symmetry::ContinuousKind::Discrete
		                          ? QString("continuous")
		                          : QString("%1 (%2)").arg(s.is_generator ? "generator" : "compound").arg(wordText(s.word));
		lines << QString::asprintf(
			"Symmetry %d: %s%s; %d -> %d vertices, source area %.3g%%, deviation rms %.3g%% max %.3g%% of the "
			"diagonal, support %d, %s",
			int(k), qUtf8Printable(kindLabel(s, diagonal)), qUtf8Printable(transformText(s)), int(s.source_vertices.size()),
			int(s.target_vertices.size()), 100 * s.source_area, 100 * s.rms_error, 100 * s.max_error, s.support,
			qUtf8Printable(basis));
	}
	if (result.welded_vertices > 0)
		lines << QString::asprintf(
			"%d vertices lie at the same position as another in a triangle soup or a repeated face: the filter "
			"welded them on its own copy, the mesh is unchanged (Cleaning "
			"and Repairing > Remove Duplicate Vertices welds them in the mesh itself).",
			result.welded_vertices);
	if (result.repeated_faces + result.back_faces > 0)
		lines << QString::asprintf(
			"%d faces repeat another face over the same three vertex positions, %d of them the other way round "
			"(the back of a double-sided surface): the filter kept one face of each, on its own copy, the mesh is "
			"unchanged (Cleaning and Repairing > Remove Duplicate Vertices, then Remove Duplicate Faces, does this to "
			"the mesh itself).",
			result.repeated_faces + result.back_faces, result.back_faces);
	if (result.flipped_faces > 0)
		lines << QString::asprintf(
			"%d faces were turned against the others around them or inward: the filter oriented each part "
			"coherently, closed ones outward, on its own copy, the mesh is unchanged (Normals, Curvatures and "
			"Orientation > Re-Orient all faces coherently does this to the mesh itself).",
			result.flipped_faces);
	if (!result.orientable)
		lines << "The mesh is not orientable (a Moebius band, or faces folded through non-manifold edges): it was "
		         "analysed with its faces as they are, and symmetries where the orientation changes may be missed.";
	if (result.point_cloud)
		lines << QString::asprintf(
			"The mesh is a point cloud of %d points: curvature came from a fit to the points around each sample, "
			"verification grew over each point's %d nearest neighbours, and the normals were %s.",
			int(host.V.rows()), options.point_cloud.graph_neighbours,
			result.normals_estimated ? "estimated from the points (as Normals, Curvatures and Orientation > "
			                           "Compute normals for point sets does, then turned outward)"
			                         : "the cloud's own");
	if (result.working_vertices > 0 && result.point_cloud)
		lines << QString::asprintf(
			"The point cloud has %d points, more than the working resolution (max_working_vertices = %d): it was "
			"analysed on %d of them spread evenly (a Poisson-disk subset, as Sampling > Point Cloud Simplification "
			"makes), and the patches and deviations are those of every point.",
			int(host.V.rows()), options.working.max_vertices, result.working_vertices);
	else if (result.working_refined)
		lines << QString::asprintf(
			"The mesh is coarse for the curvature ball (long edges, as CAD exports lay long thin triangles over "
			"flat faces): it was analysed on a copy whose long edges were split at their midpoints, %d vertices "
			"on the same surface, and the patches and deviations are those of the mesh itself.",
			result.working_vertices);
	else if (result.working_vertices > 0)
		lines << QString::asprintf(
			"The mesh has %d vertices, more than the working resolution (max_working_vertices = %d): it was "
			"analysed on a copy simplified to %d vertices, and the patches and deviations are those of the mesh "
			"itself.",
			int(host.V.rows()), options.working.max_vertices, result.working_vertices);
	if (result.pair_sample_count_automatic) {
		const symmetry::SampleSize& n = result.pair_sample_size;
		lines << QString::asprintf(
			"Paired samples: n' = %d of %d. The Appendix's bound (Equation 1) for patches of %.3g%% of the samples "
			"found with probability %.3g%% (mu = %.1f points in transformation space per paired sample) %s.",
			result.pairs_sample_count_used, result.pruned_samples, 100 * n.p, 100 * (1 - n.alpha),
			result.partners_per_sample,
			qUtf8Printable(n.bound_met ? QString("asks for n' = %1").arg(n.n_prime)
			                           : QString("is not met even by pairing every sample; more samples "
			                                     "(sample_count) would meet it")));
		if (result.rigid_pair_sample_count > 0 && result.rigid_pair_sample_count <= result.pairs_sample_count_used)
			lines << QString::asprintf(
				"A restricted group pairs no more samples than rotations and reflections would (n' = %d): its "
				"votes are those of the full group's pairs that are of its kind.",
				result.rigid_pair_sample_count);
	}
	if (result.symmetries.empty())
		lines << QString::asprintf(
			"No symmetry found: none of the %d clusters verified maps min_patch_area (%.3g%% of the area) or more "
			"of the surface onto itself within verification_tolerance (%.3g%% of the diagonal).",
			result.verified_candidates, 100 * options.min_patch_area, 100 * options.verification_tolerance);
	lines << QString::asprintf(
		"%d symmetries (%d generators) from %d samples (%d after pruning), %d pairs, %d clusters; "
		"%.2f s signatures, %.2f s pairing, %.2f s clustering, %.2f s verification",
		int(result.symmetries.size()), result.generator_count, result.samples, result.pruned_samples, result.pairs,
		result.clusters, result.seconds_signatures, result.seconds_pairing, result.seconds_clustering,
		result.seconds_verification);
	return lines;
}

Symmetrization symmetrizeMesh(CMeshO& m, const RichParameterList& parameters, const symmetry::Progress& report)
{
	Symmetrization s;
	// Its own parameters first: a wrong strength is said before minutes of detection.
	s.options = symmetry_parameters::symmetrizationOptions(parameters);
	callCore("Symmetrization", [&] { s.options.validate(); });
	const Detection detection = runDetection(m, parameters, report, 80);
	s.symmetryCount = int(detection.result.symmetries.size());
	callCore("Symmetrization", [&] {
		if (report)
			report(80, "Symmetrization");
		s.moved = symmetry::symmetrize(detection.host.V, detection.host.F, detection.result,
		                               detection.options.verification_tolerance, s.options);
	});

	// Symmetrization succeeded: from here on the mesh is written.
	const HostMesh& host = detection.host;
	for (Eigen::Index row = 0; row < host.V.rows(); ++row)
		if (s.moved.V.row(row) != host.V.row(row))
			host.vertexOfRow[size_t(row)]->P() =
				Point3m(Scalarm(s.moved.V(row, 0)), Scalarm(s.moved.V(row, 1)), Scalarm(s.moved.V(row, 2)));
	vcg::tri::UpdateNormal<CMeshO>::PerVertexNormalizedPerFaceNormalized(m);
	vcg::tri::UpdateBounding<CMeshO>::Box(m);
	return s;
}

QString symmetrizationLog(const Symmetrization& s)
{
	return QString::asprintf(
		"Symmetrized %d vertices under %d symmetries: RMS deviation from perfect symmetry %.3g%% -> %.3g%% of the "
		"diagonal (strength %.2f, %d passes).",
		s.moved.moved_vertices, s.symmetryCount, 100 * s.moved.rms_before, 100 * s.moved.rms_after, s.options.strength,
		s.options.iterations);
}

namespace {

/// Writes `bytes` to `path`, or throws an MLException saying why not.
void writeFile(const QString& path, const QByteArray& bytes)
{
	QFile file(path);
	if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate) || file.write(bytes) != bytes.size())
		throw MLException(QString("Symmetry-based reduction could not write the instances file %1 (%2). Nothing was "
		                          "added to the document.")
		                      .arg(path, file.errorString()));
}

}  // namespace

Reduction reduceMesh(MeshDocument& md, MeshModel& input, const RichParameterList& parameters,
                     const symmetry::Progress& report)
{
	Reduction r;
	const Detection detection = runDetection(input.cm, parameters, report, 80);
	r.symmetryCount = int(detection.result.symmetries.size());
	r.inputFaces = int(detection.host.F.rows());
	callCore("Symmetry-based reduction", [&] {
		if (report)
			report(80, "Symmetry-based reduction");
		r.reduced = symmetry::reduce_by_symmetry(detection.host.V, detection.host.F, detection.result,
		                                         detection.options.verification_tolerance, symmetry::ReductionOptions());
	});
	// The file first: if it cannot be written, the document is still as it was.
	r.instancesFile = symmetry_parameters::instancesFile(parameters);
	if (!r.instancesFile.isEmpty())
		writeFile(r.instancesFile, instancesJson(r));
	try {
		if (symmetry_parameters::createReconstructionLayer(parameters)) {
			Eigen::MatrixX3d V;
			Eigen::MatrixX3i F;
			symmetry::reconstruct(detection.host.V, detection.host.F, r.reduced, V, F);
			r.reconstructionLayerId = int(addMeshLayer(md, V, F, "symmetry_reconstruction")->id());
		}
		r.reducedLayerId = int(addFaceLayer(md, detection.host, r.reduced.kept_faces, "symmetry_reduced", true)->id());
	}
	catch (const std::bad_alloc&) {
		throw MLException("Symmetry-based reduction ran out of memory while writing its results.");
	}
	return r;
}

QByteArray instancesJson(const Reduction& r)
{
	const std::vector<int>& kept = r.reduced.kept_faces;
	QJsonArray instances;
	for (const symmetry::ReducedInstance& instance : r.reduced.instances) {
		QJsonArray word, matrix, faces;
		for (int k : instance.word)
			word.append(k);
		const Eigen::Matrix4d m = instance.transform.matrix();
		for (int i = 0; i < 4; ++i)
			for (int j = 0; j < 4; ++j)
				matrix.append(m(i, j));
		// The reduced mesh holds the kept faces in increasing order: a face's index there is
		// its place in kept_faces.
		for (int f : instance.faces)
			faces.append(int(std::lower_bound(kept.begin(), kept.end(), f) - kept.begin()));
		QJsonObject o;
		o["symmetries"] = word;
		o["transform"] = matrix;
		o["faces"] = faces;
		o["removed_faces"] = instance.removed_faces;
		instances.append(o);
	}
	QJsonObject root;
	root["input_faces"] = r.inputFaces;
	root["reduced_faces"] = int(kept.size());
	root["size_ratio"] = r.reduced.size_ratio;
	root["reconstruction_error"] = r.reduced.reconstruction_error;
	root["instances"] = instances;
	return QJsonDocument(root).toJson(QJsonDocument::Indented);
}

QString reductionLog(const Reduction& r)
{
	QString line = QString::asprintf(
		"Reduced %d faces to %d (%.3g%%) under %d symmetries: %d instances rebuild the rest, within %.3g%% of the "
		"diagonal.",
		r.inputFaces, int(r.reduced.kept_faces.size()), 100 * r.reduced.size_ratio, r.symmetryCount,
		int(r.reduced.instances.size()), 100 * r.reduced.reconstruction_error);
	if (!r.instancesFile.isEmpty())
		line += " Instances written to " + r.instancesFile + ".";
	return line;
}

MeshModel* originalMesh(MeshDocument& md, const RichParameterList& parameters)
{
	return meshParameter(md, parameters, "original_mesh");
}

Editing carryEdit(MeshModel& original, MeshModel& edited, const RichParameterList& parameters,
                  const symmetry::Progress& report)
{
	if (&original == &edited)
		throw MLException("Consistent editing needs two meshes: the original (original_mesh) and its edited copy "
		                  "(the current mesh); both name the same mesh. Duplicate the mesh, edit the copy, and run the "
		                  "filter on the copy with the original as original_mesh.");
	const HostMesh copy = copyMesh(edited.cm);
	const Detection detection = runDetection(original.cm, parameters, report, 80);
	if (copy.F.rows() != detection.host.F.rows() || copy.F != detection.host.F)
		throw MLException(QString("The edited mesh has %1 faces and the original %2, or other ones: consistent editing "
		                          "needs the original's vertices and faces, some vertices moved, not a remeshed copy. The "
		                          "mesh was left unchanged.")
		                      .arg(copy.F.rows())
		                      .arg(detection.host.F.rows()));
	Editing e;
	e.symmetryCount = int(detection.result.symmetries.size());
	callCore("Consistent editing", [&] {
		if (report)
			report(80, "Consistent editing");
		e.moved = symmetry::carry_edit(detection.host.V, detection.host.F, copy.V, detection.result,
		                               detection.options.verification_tolerance, symmetry::EditingOptions());
	});
	// Editing succeeded: from here on the mesh is written.
	for (Eigen::Index row = 0; row < copy.V.rows(); ++row)
		if (e.moved.V.row(row) != copy.V.row(row))
			copy.vertexOfRow[size_t(row)]->P() =
				Point3m(Scalarm(e.moved.V(row, 0)), Scalarm(e.moved.V(row, 1)), Scalarm(e.moved.V(row, 2)));
	vcg::tri::UpdateNormal<CMeshO>::PerVertexNormalizedPerFaceNormalized(edited.cm);
	vcg::tri::UpdateBounding<CMeshO>::Box(edited.cm);
	return e;
}

QString editingLog(const Editing& e)
{
	return QString::asprintf(
		"Carried the edit of %d vertices to %d vertices of their copies under %d symmetries (%d passes along chains "
		"of copies).",
		e.moved.edited_vertices, e.moved.carried_vertices, e.symmetryCount, e.moved.passes);
}

namespace {

// Per-vertex Scalarm attribute `segment_id` (replacing one left by an earlier run) and a
// colour per segment, grey where none holds.  Deleted vertices get -1.
void writeSegmentIds(MeshModel& mm, const HostMesh& h, const std::vector<int>& segmentOfRow, int segments)
{
	writeVertexIdAttribute(mm.cm, h, segmentOfRow, "segment_id");
	mm.updateDataMask(MeshModel::MM_VERTCOLOR);
	for (size_t row = 0; row < h.vertexOfRow.size(); ++row) {
		const int k = segmentOfRow[row];
		h.vertexOfRow[row]->C() =
			k < 0 ? vcg::Color4b(vcg::Color4b::Gray) : vcg::Color4b::Scatter(std::max(segments, 2), k);
	}
}

}  // namespace

Segmentation segmentPoses(MeshDocument& md, const RichParameterList& parameters, const symmetry::Progress& report)
{
	MeshModel* firstPose = meshParameter(md, parameters, "first_mesh");
	MeshModel* secondPose = meshParameter(md, parameters, "second_mesh");
	if (firstPose == nullptr || secondPose == nullptr)
		throw MLException("Rigid segmentation needs two meshes of the document: first_mesh and second_mesh.");
	MeshModel& first = *firstPose;
	MeshModel& second = *secondPose;
	if (&first == &second)
		throw MLException("Rigid segmentation needs two poses, but first_mesh and second_mesh name the same mesh. "
		                  "Load the shape in its second pose and choose it as second_mesh.");
	Segmentation s;
	HostMesh firstHost, secondHost;
	callCore("Rigid segmentation", [&] {
		// The host turned the percentages into lengths with the first pose's diagonal.
		const double diagonal = first.cm.bbox.IsNull() ? 0.0 : double(first.cm.bbox.Diag());
		const symmetry::DetectionOptions options = symmetry_parameters::fromRichParameterList(parameters, diagonal);
		firstHost = copyMesh(first.cm);
		secondHost = copyMesh(second.cm);
		s.found = symmetry::segment_rigid_parts(firstHost.V, firstHost.F, secondHost.V, secondHost.F, options,
		                                        symmetry::SegmentationOptions(), report);
	});
	if (s.found.first_segment_id.size() != size_t(firstHost.V.rows()) ||
	    s.found.second_segment_id.size() != size_t(secondHost.V.rows()))
		throw MLException("Rigid segmentation failed because of an internal error (its labels do not fit the "
		                  "meshes). The meshes were left unchanged; please report this with the meshes.");
	s.firstRows = int(firstHost.V.rows());
	s.diagonal = first.cm.bbox.IsNull() ? 1.0 : double(first.cm.bbox.Diag());
	s.secondRows = int(secondHost.V.rows());
	// Segmentation succeeded: from here on the document is written.
	const int segments = int(s.found.segments.size());
	writeSegmentIds(first, firstHost, s.found.first_segment_id, segments);
	writeSegmentIds(second, secondHost, s.found.second_segment_id, segments);
	s.layerIds.assign(size_t(2 * segments), -1);
	if (symmetry_parameters::createSegmentLayers(parameters)) {
		try {
			for (int k = 0; k < segments; ++k) {
				const symmetry::RigidSegment& segment = s.found.segments[size_t(k)];
				const QString name = QString("segment_%1_").arg(k);
				s.layerIds[size_t(2 * k)] = int(addPatchLayer(md, firstHost, segment.first_vertices, name + "first")->id());
				s.layerIds[size_t(2 * k + 1)] =
					int(addPatchLayer(md, secondHost, segment.second_vertices, name + "second")->id());
			}
		}
		catch (const std::bad_alloc&) {
			throw MLException("Rigid segmentation ran out of memory while adding its layers.");
		}
	}
	return s;
}

QStringList segmentationLog(const Segmentation& s)
{
	QStringList lines;
	int firstLabelled = 0, secondLabelled = 0;
	for (size_t k = 0; k < s.found.segments.size(); ++k) {
		const symmetry::RigidSegment& segment = s.found.segments[k];
		firstLabelled += int(segment.first_vertices.size());
		secondLabelled += int(segment.second_vertices.size());
		symmetry::DetectedSymmetry motion;
		motion.transform = segment.transform;
		lines << QString("Segment %1: %2 vertices of the first pose, %3 of the second, moved by a %4%5; RMS deviation "
		                 "%6% of the diagonal.")
		             .arg(k)
		             .arg(segment.first_vertices.size())
		             .arg(segment.second_vertices.size())
		             .arg(kindLabel(motion, s.diagonal))
		             .arg(transformText(motion))
		             .arg(100 * segment.rms_error, 0, 'g', 3);
	}
	const symmetry::DetectionResult& d = s.found.detection;
	lines << QString("Rigid segmentation: %1 segments; %2% of the first pose's vertices and %3% of the second's "
	                 "labelled (%4 samples, %5 pairs between the poses, %6 clusters verified; %7 s).")
	             .arg(s.found.segments.size())
	             .arg(100.0 * firstLabelled / std::max(1, s.firstRows), 0, 'f', 1)
	             .arg(100.0 * secondLabelled / std::max(1, s.secondRows), 0, 'f', 1)
	             .arg(d.samples)
	             .arg(d.pairs)
	             .arg(d.verified_candidates)
	             .arg(d.seconds_signatures + d.seconds_pairing + d.seconds_clustering + d.seconds_verification, 0, 'f',
	                  1);
	return lines;
}

}  // namespace symmetry_host
