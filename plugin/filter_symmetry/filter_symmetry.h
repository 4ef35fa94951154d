// MeshLab 2025.07 adapter for partial and approximate symmetry detection
// (Mitra, Guibas, Pauly, SIGGRAPH 2006).  It converts the current mesh and the
// parameters for the core (plugin/core/detection.h), calls it, and writes the
// result back as vertex quality, colour, a `symmetry_id` attribute and patch layers.
// It holds no algorithm.
#pragma once

#include <common/plugins/interfaces/filter_plugin.h>

namespace symmetry_host {
enum class Filter;  // host_mesh.h
}

class FilterSymmetryPlugin : public QObject, public FilterPlugin
{
	Q_OBJECT
	MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
	Q_INTERFACES(FilterPlugin)

public:
	enum { FP_PARTIAL_SYMMETRIES, FP_SYMMETRIZATION, FP_REDUCTION, FP_EDITING, FP_SEGMENTATION };

	FilterSymmetryPlugin();

	/// "FilterSymmetry".
	QString pluginName() const override;
	/// The menu entries, "Detect Partial and Approximate Symmetries", "Symmetrize
	/// Approximate Symmetries", "Symmetry-Based Reduction", "Carry an Edit to Symmetric Copies" and
	/// "Segment Rigid Parts Between Two Poses".
	QString filterName(ActionIDType filter) const override;
	/// compute_partial_symmetries, apply_coord_symmetrization, generate_symmetry_based_reduction,
	/// apply_coord_consistent_editing, compute_rigid_segments_between_meshes: public API, never rename.
	QString pythonFilterName(ActionIDType filter) const override;
	/// Paper reference and the meaning of every output.
	QString filterInfo(ActionIDType filter) const override;
	FilterClass getClass(const QAction* action) const override;
	/// SINGLE_MESH: the current mesh is the input; FIXED for segmentation, whose two meshes are
	/// parameters.
	FilterArity filterArity(const QAction* action) const override;
	/// None: the core itself refuses what it cannot analyse, saying what to do (a point cloud).
	int getPreConditions(const QAction* action) const override;
	/// Detection: vertex quality and colour, and vertex and face numbers for the layers it
	/// adds (so the GUI offers no preview).  Symmetrization: vertex positions and normals.
	/// Reduction: vertex and face numbers (it adds layers).
	int postCondition(const QAction* action) const override;
	/// The parameters in their public order, defaults from symmetry::DetectionOptions; for
	/// consistent editing also the original mesh, a mesh of the document.
	RichParameterList initParameterList(const QAction* action, const MeshDocument& md) override;
	using FilterPlugin::initParameterList;
	/// Dispatches to detectPartialSymmetries().
	std::map<std::string, QVariant> applyFilter(
		const QAction* action,
		const RichParameterList& parameters,
		MeshDocument& md,
		unsigned int& postConditionMask,
		vcg::CallBackPos* cb) override;

private:
	/// Runs the core on the current mesh and, only once it has succeeded, writes the
	/// outputs.  Every failure becomes an MLException and leaves the document unchanged.
	std::map<std::string, QVariant> detectPartialSymmetries(
		MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);
	/// Detects, then moves each approximately symmetric patch pair towards its exactly
	/// symmetric average (core/symmetrization.h).  The mesh is changed only on success.
	std::map<std::string, QVariant> symmetrize(
		MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);

	/// Removes the faces that are copies of others (core/reduction.h), as new layers; the
	/// input is not changed.
	std::map<std::string, QVariant> reduce(
		MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);

	/// Carries an edit of the current mesh to the copies of the edited part (core/consistent_editing.h).
	std::map<std::string, QVariant> carryEdit(
		MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);

	/// Labels the rigid parts between first_mesh and second_mesh (core/rigid_segmentation.h).
	std::map<std::string, QVariant> segment(
		MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);

	/// Which of the filters `action` is (host_mesh.h's Filter).
	symmetry_host::Filter filterOf(const QAction* action) const;
};
