// The MeshLab headers a host-side file needs, for either plugin API the adapters are built
// for: 2025.07 (pymeshlab, the GUI; the default) or 2020.09 (Debian 12's meshlabserver,
// built with SYMMETRY_MESHLAB_2020_09 defined).  The two differ in where the headers live
// and in the name of the percentage parameter; the mesh types, the document and the
// parameter list are otherwise the same.
#pragma once

#ifdef SYMMETRY_MESHLAB_2020_09
#include <common/interfaces.h>
#include <common/filter_parameter/rich_parameter_list.h>
/// 2020.09 calls a length given as a percentage of the diagonal an "absolute percentage".
using RichPercentage = RichAbsPerc;
#else
#include <common/ml_document/mesh_document.h>
#include <common/parameters/rich_parameter_list.h>
#endif
#include <common/mlexception.h>

/// The document a parameter list is made for: 2020.09 hands it over mutable, 2025.07 const.
#ifdef SYMMETRY_MESHLAB_2020_09
using ParameterDocument = MeshDocument&;
#else
using ParameterDocument = const MeshDocument&;
#endif
