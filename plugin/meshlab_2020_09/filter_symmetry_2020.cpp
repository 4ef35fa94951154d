#include "filter_symmetry_2020.h"

#include <filter_symmetry/filter_texts.h>
#include <filter_symmetry/host_mesh.h>
#include <filter_symmetry/symmetry_parameters.h>

#include <core/detection.h>
#include <core/symmetrization.h>

#include <optional>
#include <string>

namespace {

/// MeshLab's progress callback as the core's.  meshlabserver prints every string it is
/// given, with no line break and no percentage; so each stage is passed once, as a line of
/// its own ("Symmetry detection: Verification by region growing (45%)").
symmetry::Progress progressOf(vcg::CallBackPos* cb)
{
	if (cb == nullptr)
		return {};
	return [cb, last = std::string()](int percent, const char* stage) mutable {
		if (last == stage)
			return;
		last = stage;
		const std::string line = "Symmetry detection: " + last + " (" + std::to_string(percent) + "%)\n";
		cb(percent, line.c_str());
	};
}

}  // namespace

FilterSymmetryPlugin::FilterSymmetryPlugin()
{
	typeList = {FP_PARTIAL_SYMMETRIES, FP_SYMMETRIZATION, FP_REDUCTION, FP_EDITING, FP_SEGMENTATION};
	for (FilterIDType id : types())
		actionList.push_back(new QAction(filterName(id), this));
}

QString FilterSymmetryPlugin::pluginName() const
{
	return "FilterSymmetry";
}

QString FilterSymmetryPlugin::filterName(FilterIDType filter) const
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

QString FilterSymmetryPlugin::filterInfo(FilterIDType filter) const
{
	switch (filter) {
	case FP_PARTIAL_SYMMETRIES: return symmetry_texts::detectionInfo(false);
	case FP_SYMMETRIZATION: return symmetry_texts::symmetrizationInfo(false);
	case FP_REDUCTION: return symmetry_texts::reductionInfo(false);
	case FP_EDITING: return symmetry_texts::editingInfo(false);
	case FP_SEGMENTATION: return symmetry_texts::segmentationInfo(false);
	default: assert(0); return QString();
	}
}

MeshFilterInterface::FilterClass FilterSymmetryPlugin::getClass(QAction* action)
{
	switch (ID(action)) {
	case FP_SYMMETRIZATION:
	case FP_EDITING: return MeshFilterInterface::Smoothing;
	case FP_REDUCTION: return MeshFilterInterface::Remeshing;
	default: return MeshFilterInterface::Measure;
	}
}

MeshFilterInterface::FILTER_ARITY FilterSymmetryPlugin::filterArity(QAction* action) const
{
	return ID(action) == FP_SEGMENTATION ? FIXED : SINGLE_MESH;
}

int FilterSymmetryPlugin::getPreConditions(QAction*) const
{
	return MeshModel::MM_NONE;
}

int FilterSymmetryPlugin::postCondition(QAction* action) const
{
	return symmetry_host::changedData(filterOf(action));
}

void FilterSymmetryPlugin::initParameterSet(QAction* action, MeshDocument& md, RichParameterList& parameters)
{
	symmetry_host::appendParameters(filterOf(action), md, parameters);
}

symmetry_host::Filter FilterSymmetryPlugin::filterOf(QAction* action) const
{
	switch (ID(action)) {
	case FP_SYMMETRIZATION: return symmetry_host::Filter::Symmetrization;
	case FP_REDUCTION: return symmetry_host::Filter::Reduction;
	case FP_EDITING: return symmetry_host::Filter::Editing;
	case FP_SEGMENTATION: return symmetry_host::Filter::Segmentation;
	default: return symmetry_host::Filter::Detection;
	}
}

bool FilterSymmetryPlugin::applyFilter(QAction* action, MeshDocument& md, const RichParameterList& parameters,
                                       vcg::CallBackPos* cb)
{
	// 2020.09's hosts do not catch exceptions from a filter: every failure becomes the
	// boolean and the sentence this interface has for it.
	try {
		switch (ID(action)) {
		case FP_PARTIAL_SYMMETRIES: detectPartialSymmetries(md, parameters, cb); break;
		case FP_SYMMETRIZATION: symmetrize(md, parameters, cb); break;
		case FP_REDUCTION: reduce(md, parameters, cb); break;
		case FP_EDITING: carryEdit(md, parameters, cb); break;
		case FP_SEGMENTATION: segment(md, parameters, cb); break;
		default: throw MLException("Unknown filter of the symmetry plugin.");
		}
		return true;
	}
	catch (const std::exception& e) {  // MLException, with the sentence for the user
		errorMessage = QString::fromLocal8Bit(e.what());
	}
	catch (...) {
		errorMessage = "The symmetry filter failed because of an unknown internal error. The mesh was left unchanged.";
	}
	Log(GLLogStream::WARNING, qUtf8Printable(errorMessage));
	return false;
}

void FilterSymmetryPlugin::detectPartialSymmetries(MeshDocument& md, const RichParameterList& parameters,
                                                   vcg::CallBackPos* cb)
{
	MeshModel* input = md.mm();
	if (input == nullptr)
		throw MLException("There is no current mesh to detect symmetries on.");
	const symmetry_host::Detection detection = symmetry_host::runDetection(input->cm, parameters, progressOf(cb), 100, true);
	// Detection succeeded: from here on the document is written.
	symmetry_host::writeDetection(md, *input, detection, symmetry_parameters::createPatchLayers(parameters));
	for (const QString& line : symmetry_host::detectionLog(detection))
		Log(qUtf8Printable(line));
}

void FilterSymmetryPlugin::symmetrize(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* input = md.mm();
	if (input == nullptr)
		throw MLException("There is no current mesh to symmetrize.");
	const symmetry_host::Symmetrization done = symmetry_host::symmetrizeMesh(input->cm, parameters, progressOf(cb));
	Log(qUtf8Printable(symmetry_host::symmetrizationLog(done)));
}

void FilterSymmetryPlugin::reduce(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* input = md.mm();
	if (input == nullptr)
		throw MLException("There is no current mesh to reduce.");
	const symmetry_host::Reduction done = symmetry_host::reduceMesh(md, *input, parameters, progressOf(cb));
	Log(qUtf8Printable(symmetry_host::reductionLog(done)));
}

void FilterSymmetryPlugin::carryEdit(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	MeshModel* edited = md.mm();
	MeshModel* original = symmetry_host::originalMesh(md, parameters);
	if (edited == nullptr || original == nullptr)
		throw MLException("Consistent editing needs the edited mesh as the current mesh and the original as original_mesh.");
	const symmetry_host::Editing done = symmetry_host::carryEdit(*original, *edited, parameters, progressOf(cb));
	Log(qUtf8Printable(symmetry_host::editingLog(done)));
}

void FilterSymmetryPlugin::segment(MeshDocument& md, const RichParameterList& parameters, vcg::CallBackPos* cb)
{
	const symmetry_host::Segmentation done = symmetry_host::segmentPoses(md, parameters, progressOf(cb));
	for (const QString& line : symmetry_host::segmentationLog(done))
		Log(qUtf8Printable(line));
}
