// The host side shared by the MeshLab adapters: the 2025.07 plugin (pymeshlab and the
// GUI, filter_symmetry.cpp) and the 2020.09 plugin (meshlabserver,
// ../meshlab_2020_09/filter_symmetry_2020.cpp).  It copies the current mesh for the core,
// runs detection, and writes the result into the document: vertex quality and colour, the
// `symmetry_id` attribute, patch layers, and the log lines.  Everything here compiles
// against either MeshLab release (meshlab_api.h); what differs between them (the plugin
// interface, returned values) stays in the adapters.
#pragma once

#include "meshlab_api.h"

#include <core/detection.h>
#include <core/consistent_editing.h>
#include <core/reduction.h>
#include <core/rigid_segmentation.h>
#include <core/symmetrization.h>

#include <Eigen/Core>
#include <new>
#include <stdexcept>
#include <vector>

namespace symmetry_host {

/// The filters every adapter offers.
enum class Filter { Detection, Symmetrization, Reduction, Editing, Segmentation };

/// What `filter` changes in the document, as MeshLab's data mask (the same in every
/// release): the adapters' postCondition.
int changedData(Filter filter);

/// The parameters of `filter`, in their public order, defaults from the core's options;
/// `diagonal` is that of the mesh the dialog opens on.  The adapters' parameter list.
void appendParameters(Filter filter, double diagonal, RichParameterList& parameters);

/// The parameters of `filter` for a dialog opened on the document `md` (its current mesh's
/// diagonal): appendParameters(), and for consistent editing the mesh parameter
/// original_mesh, by default another mesh than the current one (the edited).  Rigid
/// segmentation takes first_mesh (by default the current one) and second_mesh (another),
/// then the detection parameters but the group and the basis reduction's.
void appendParameters(Filter filter, ParameterDocument md, RichParameterList& parameters);

/// The current mesh as the core sees it: non-deleted vertices and faces, compacted.
struct HostMesh {
	Eigen::MatrixX3d V;                  ///< #V by 3 positions
	Eigen::MatrixX3i F;                  ///< #F by 3 rows of V
	std::vector<CVertexO*> vertexOfRow;  ///< the CMeshO vertex behind each row of V
};

/// The non-deleted vertices and faces of `m`.  Throws symmetry::InputError on a face that
/// refers past the vertex array (a malformed file).
HostMesh copyMesh(CMeshO& m);

/// A result that does not fit the input would corrupt the document: refuse it before
/// anything is written.  Throws std::logic_error (a bug in the core, not user error).
void checkResult(const symmetry::DetectionResult& r, Eigen::Index rows, const symmetry::DetectionOptions& o);

/// v.Q() = signed deviation (fraction of the diagonal); colour ramp over [-m, m],
/// grey where no symmetry holds.
void writeQualityAndColour(MeshModel& mm, const HostMesh& h, const symmetry::DetectionResult& r);

/// Per-vertex Scalarm attribute `symmetry_id`, replacing one left by an earlier run
/// (whatever its type).  Deleted vertices get -1.
void writeSymmetryIdAttribute(CMeshO& m, const HostMesh& h, const symmetry::DetectionResult& r);

/// A new layer `name` (not made current) holding copies of the input vertices in `rows`
/// (with position, normal, colour, quality) and of the faces whose three vertices are all
/// among them.
MeshModel* addPatchLayer(MeshDocument& md, const HostMesh& h, const std::vector<int>& rows, const QString& name);

/// A new layer `name` holding copies of the input faces `faceRows` (rows of h.F) and of their
/// vertices, made current if `makeCurrent`.
MeshModel* addFaceLayer(MeshDocument& md, const HostMesh& h, const std::vector<int>& faceRows, const QString& name,
                        bool makeCurrent);

/// A new layer `name` (not made current) holding the triangle mesh (V, F).
MeshModel* addMeshLayer(MeshDocument& md, const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const QString& name);

// What a reported symmetry is, in words: a continuous family with its axis, or the kind of
// the discrete transformation (a rotation whose axis it also slides along is a screw, a
// mirror that also slides along its plane a glide reflection, a mirror composed with a turn
// about its normal a rotoreflection).  `diagonal` sets the
// lengths below which a slide is none.
QString kindLabel(const symmetry::DetectedSymmetry& s, double diagonal);

/// A basis word as text: "+g0 -g1", or "identity".
QString wordText(const symmetry::Word& word);

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

/// Runs the core's detection on `m` with the filter's parameters, reporting progress
/// through `report` (may be empty) from 0 to `progressEnd` percent, on this thread.  Writes
/// nothing.  With `pointCloudAllowed`, a mesh with vertices and no face is analysed as a
/// point cloud, with its own normals when every vertex has one (MeshLab keeps zero normals
/// for a cloud read without any) and with normals estimated otherwise; without, the core
/// refuses it, saying how to make a surface of it.
Detection runDetection(CMeshO& m, const RichParameterList& parameters, const symmetry::Progress& report,
                       int progressEnd, bool pointCloudAllowed = false);

/// Writes a successful detection into the document: quality and colour of the input's
/// vertices, the `symmetry_id` attribute and, if `createLayers`, the layers
/// symmetry_k_source and symmetry_k_target (the input stays the current mesh).  Returns
/// the layer ids, two per symmetry, -1 without layers.
std::vector<int> writeDetection(MeshDocument& md, MeshModel& input, const Detection& d, bool createLayers);

/// What the log says after a detection, one entry per line: one line per symmetry (its kind,
/// transformation, patch sizes and deviation), what the filter did to its copy of the
/// mesh, the n' it chose, and a summary with the stage times.
QStringList detectionLog(const Detection& d);

/// What symmetrization did to the current mesh.
struct Symmetrization {
	int symmetryCount = 0;                    ///< symmetries detected
	symmetry::SymmetrizationOptions options;  ///< strength and passes used
	symmetry::SymmetrizationResult moved;     ///< vertices moved, RMS before and after
};

/// Detects, then moves each approximately symmetric patch pair of `m` towards its exactly
/// symmetric average (core/symmetrization.h), and updates the normals and the bounding
/// box.  Its own parameters are checked before detection starts; `m` changes only on
/// success (every failure is an MLException).
Symmetrization symmetrizeMesh(CMeshO& m, const RichParameterList& parameters, const symmetry::Progress& report);

/// The log line after a symmetrization.
QString symmetrizationLog(const Symmetrization& s);

/// What symmetry-based reduction made of the current mesh.
struct Reduction {
	int symmetryCount = 0;             ///< symmetries detected
	int inputFaces = 0;                ///< faces of the input the core saw
	symmetry::ReductionResult reduced; ///< faces kept, instances, reconstruction error
	QString instancesFile;             ///< the JSON written, empty if none
	int reducedLayerId = -1;           ///< the layer of the kept faces
	int reconstructionLayerId = -1;    ///< the rebuilt model's layer, -1 if not asked for
};

/// Detects, then removes the faces that are copies of others (core/reduction.h): writes the
/// instances to the JSON file if one is named, then adds the layer symmetry_reduced (the kept
/// faces, made current) and, if asked, symmetry_reconstruction.  The input mesh is not
/// changed; on failure (an MLException) nothing is added and no file is written.
Reduction reduceMesh(MeshDocument& md, MeshModel& input, const RichParameterList& parameters,
                     const symmetry::Progress& report);

/// The instances as JSON: the input's and the reduced mesh's face counts, and per instance
/// its word (k+1 symmetry k, -(k+1) its inverse), its row-major 4x4 matrix and the faces it copies (indices into the
/// reduced mesh's faces).
QByteArray instancesJson(const Reduction& r);

/// The log line after a reduction.
QString reductionLog(const Reduction& r);

/// What consistent editing did to the current (edited) mesh.
struct Editing {
	int symmetryCount = 0;          ///< symmetries detected on the original
	symmetry::EditingResult moved;  ///< vertices the user moved, vertices that received the edit
};

/// Detects on `original`, then carries the edit (edited - original, same vertices and faces)
/// to every copy of the edited patch (core/consistent_editing.h), moving the vertices of
/// `edited`, and updates its normals and bounding box.  `edited` changes only on success
/// (every failure is an MLException).
Editing carryEdit(MeshModel& original, MeshModel& edited, const RichParameterList& parameters,
                  const symmetry::Progress& report);

/// The mesh the parameter original_mesh names.
MeshModel* originalMesh(MeshDocument& md, const RichParameterList& parameters);

/// The log line after consistent editing.
QString editingLog(const Editing& e);

/// What rigid segmentation between two poses found and wrote.
struct Segmentation {
	symmetry::SegmentationResult found;  ///< the segments, per-vertex labels of both poses
	std::vector<int> layerIds;           ///< two per segment (first pose, second pose), -1 without layers
	int firstRows = 0, secondRows = 0;   ///< vertices of either pose the core saw
	double diagonal = 1;                 ///< the first pose's: the unit of the log's lengths
};

/// Segments the rigid parts between the meshes first_mesh and second_mesh name
/// (core/rigid_segmentation.h), then colours the vertices of both by segment (grey where
/// none holds), writes their per-vertex attribute `segment_id` and, if asked, the layers
/// segment_k_first and segment_k_second.  Nothing is written on failure (an MLException).
Segmentation segmentPoses(MeshDocument& md, const RichParameterList& parameters, const symmetry::Progress& report);

/// The log lines after a segmentation: one per segment, then a summary.
QStringList segmentationLog(const Segmentation& s);

}  // namespace symmetry_host
