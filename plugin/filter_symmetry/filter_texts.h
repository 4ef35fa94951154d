// The menu entries and the help texts of the filters, shared by the MeshLab adapters so
// that the GUI, pymeshlab and meshlabserver show the same words.  The menu entries are
// public API (filter scripts name them): never rename them.
#pragma once

#include <QString>

namespace symmetry_texts {

/// "Detect Partial and Approximate Symmetries".
QString detectionName();
/// "Symmetrize Approximate Symmetries".
QString symmetrizationName();
/// "Symmetry-Based Reduction".
QString reductionName();
/// "Carry an Edit to Symmetric Copies".
QString editingName();
/// "Segment Rigid Parts Between Two Poses".
QString segmentationName();

/// The help text shown above the parameters: what the filter does, its outputs on the
/// mesh, the paper.  `returnsValues`: the host returns values to the caller (MeshLab
/// 2022 and later, pymeshlab), so their list is included; meshlabserver 2020.09 has none.
QString detectionInfo(bool returnsValues);
QString symmetrizationInfo(bool returnsValues);
QString reductionInfo(bool returnsValues);
QString editingInfo(bool returnsValues);
QString segmentationInfo(bool returnsValues);

}  // namespace symmetry_texts
