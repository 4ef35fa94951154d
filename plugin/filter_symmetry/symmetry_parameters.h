// The two-way converter between MeshLab's RichParameterList and the core's
// DetectionOptions (as filter_icp's icp_align_parameter does for AlignPair::Param).
// The parameter names are public API (pymeshlab keyword arguments): never rename them.
#pragma once

#include <core/detection.h>
#include <core/reduction.h>
#include <core/symmetrization.h>

#include <optional>

#include "meshlab_api.h"

namespace symmetry_parameters {

/// Appends the filter's parameters, in their public order, to `parameters`, with the
/// values of `options` as defaults.  `createPatchLayers` is the one parameter the core
/// does not see: it only tells the adapter whether to write the patches as layers (no such
/// parameter when it is empty: the symmetrization filter writes none).  Lengths the core takes as fractions of the
/// bounding-box diagonal become RichPercentage values; `diagonal` is the diagonal of
/// the mesh the dialog is opened on (the absolute value a percentage stands for).
/// Without `groupAndBasis`, transformation_group and the basis reduction's parameters are
/// left out (rigid segmentation between two poses fixes the group and reduces no basis).
void toRichParameterList(const symmetry::DetectionOptions& options, double diagonal,
                         std::optional<bool> createPatchLayers, RichParameterList& parameters,
                         bool groupAndBasis = true);

/// Reads the parameters back into the core's units: percentages of the diagonal become
/// fractions of `diagonal`, the patch area in percent becomes a fraction.  No range check
/// here; DetectionOptions::validate() is the one place that judges the values.  If
/// `diagonal` is not a positive finite number (a mesh with no usable bounding box), the
/// length parameters keep the core's defaults so that the mesh itself, not a derived
/// length, is what the core rejects.  Parameters left out of the list keep the core's defaults.
symmetry::DetectionOptions fromRichParameterList(const RichParameterList& parameters, double diagonal);

/// The value of create_patch_layers.
bool createPatchLayers(const RichParameterList& parameters);

/// The symmetrization filter's own parameters (strength, symmetrization_iterations),
/// appended after the detection parameters, and read back.
void appendSymmetrizationParameters(const symmetry::SymmetrizationOptions& options, RichParameterList& parameters);
symmetry::SymmetrizationOptions symmetrizationOptions(const RichParameterList& parameters);

/// The reduction filter's own parameters, appended after the detection parameters:
/// create_reconstruction_layer and instances_file (the JSON file the instances go to, none
/// when empty), which only tell the adapter what to write; the core's ReductionOptions keep
/// their defaults.
void appendReductionParameters(RichParameterList& parameters);
bool createReconstructionLayer(const RichParameterList& parameters);
QString instancesFile(const RichParameterList& parameters);

/// The segmentation filter's own parameter, appended after the detection parameters:
/// create_segment_layers, which only tells the adapter whether to add a layer per segment.
void appendSegmentationParameters(RichParameterList& parameters);
bool createSegmentLayers(const RichParameterList& parameters);

}  // namespace symmetry_parameters
