// MeshLab 2020.09 adapter, for Debian 12's meshlabserver (headless batch jobs with filter
// scripts).  The same filters as the 2025.07 adapter (../filter_symmetry), over the same
// core and the same host-side helpers (../filter_symmetry/host_mesh.h); only the plugin
// interface differs: 2020.09's MeshFilterInterface returns a bool and no values, and says
// why it failed in errorMessage and the log.  It holds no algorithm.
#pragma once

#include <filter_symmetry/meshlab_api.h>

namespace symmetry_host {
enum class Filter;  // host_mesh.h
}

class FilterSymmetryPlugin : public QObject, public MeshFilterInterface
{
	Q_OBJECT
	MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
	Q_INTERFACES(MeshFilterInterface)

public:
	enum { FP_PARTIAL_SYMMETRIES, FP_SYMMETRIZATION, FP_REDUCTION, FP_EDITING, FP_SEGMENTATION };

	FilterSymmetryPlugin();

	/// "FilterSymmetry".
	QString pluginName() const override;
	/// The menu entries, the names a filter script (.mlx) uses: "Detect Partial and
	/// Approximate Symmetries", "Symmetrize Approximate Symmetries", "Symmetry-Based Reduction",
	/// "Carry an Edit to Symmetric Copies" and "Segment Rigid Parts Between Two Poses".
	QString filterName(FilterIDType filter) const override;
	/// Paper reference and the meaning of every output written to the mesh.
	QString filterInfo(FilterIDType filter) const override;
	FilterClass getClass(QAction* action) override;
	/// SINGLE_MESH: the current mesh is the input; FIXED for segmentation (two mesh parameters).
	FILTER_ARITY filterArity(QAction* action) const override;
	/// None: the core itself refuses what it cannot analyse, saying what to do.
	int getPreConditions(QAction* action) const override;
	/// Detection: vertex quality and colour.  Symmetrization: positions and normals.
	/// Reduction: vertex and face numbers (new layers).
	int postCondition(QAction* action) const override;
	/// The parameters in their public order (the names a filter script uses), defaults
	/// from symmetry::DetectionOptions.
	void initParameterSet(QAction* action, MeshDocument& md, RichParameterList& parameters) override;
	using MeshFilterInterface::initParameterSet;
	/// Runs the filter; on failure returns false, with the reason in errorMessage and in
	/// the log (meshlabserver prints the log, not errorMessage), the document unchanged.
	bool applyFilter(QAction* action, MeshDocument& md, const RichParameterList& parameters,
	                 vcg::CallBackPos* cb) override;

private:
	void detectPartialSymmetries(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);
	void symmetrize(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);
	void reduce(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);
	void carryEdit(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);
	void segment(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb);

	/// Which of the filters `action` is (host_mesh.h's Filter).
	symmetry_host::Filter filterOf(QAction* action) const;
};
