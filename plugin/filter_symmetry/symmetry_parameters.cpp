#include "symmetry_parameters.h"

#include <cmath>

namespace symmetry_parameters {

namespace {

// Display names of the transformation groups; the index is public API and equals
// the value of symmetry::TransformationGroup.
QStringList groupNames()
{
	return QStringList{
		"Rotations, reflections and translations (rigid, 6-D)",
		"Similarities: rigid plus uniform scale (7-D)",
		"Reflections only",
		"Translations only"};
}

bool usableDiagonal(double diagonal)
{
	return std::isfinite(diagonal) && diagonal > 0;
}

// The transformation group (§2).
void appendGroupParameter(const symmetry::DetectionOptions& o, RichParameterList& parameters)
{
	parameters.addParam(RichEnum(
		"transformation_group", int(o.group), groupNames(), "Transformation group",
		"The symmetries looked for (§2 of the paper). Rigid (the default, when you do not know what to "
		"expect): every rotation, reflection and translation that maps a part of the surface onto another "
		"part, e.g. the mirror of a face and the repeated wheels of a car. Similarities: rigid plus uniform "
		"scaling, for parts repeated at different sizes, e.g. the chambers of a shell. Reflections only: "
		"mirror planes, global or partial, e.g. the plane of a scanned head; it reports the mirror planes "
		"the rigid group finds, usually in less time, and nothing else (a mirrored copy set down in another "
		"orientation is a mirror composed with a turn: rigid group only). Translations only: parts repeated "
		"in the same orientation, e.g. the windows of a facade or the teeth of a rack."));
}

// Algorithm 1's switches (§4.1); `d` is the diagonal the percentages stand for.
void appendBasisParameters(const symmetry::DetectionOptions& o, double d, RichParameterList& parameters)
{
	parameters.addParam(RichBool(
		"reduce_basis", o.reduce_basis, "Reduce to generators",
		"Run the symmetry basis reduction of §4.1 (Algorithm 1): write compound symmetries as words in a "
		"few generating transformations."));
	parameters.addParam(RichInt(
		"basis_loop_length", o.basis_loop_length, "Basis word length",
		"The paper's eta (Algorithm 1): longest product of generators tried when expressing a symmetry."));
	parameters.addParam(RichPercentage(
		"basis_tolerance", o.basis_tolerance * d, 0, d, "Basis tolerance",
		"The paper's delta (Algorithm 1): a symmetry within this distance of a product of generators, in "
		"transformation space, is a compound of them rather than a new generator."));
}

}  // namespace

void toRichParameterList(const symmetry::DetectionOptions& o, double diagonal, std::optional<bool> createPatchLayers,
                         RichParameterList& parameters, bool groupAndBasis)
{
	// A dialog opened on an empty mesh still needs a scale for its percentages.
	const double d = usableDiagonal(diagonal) ? diagonal : 1.0;

	if (groupAndBasis)
		appendGroupParameter(o, parameters);
	parameters.addParam(RichInt(
		"sample_count", o.sample_count, "Surface samples",
		"Number of points sampled uniformly on the surface before umbilic pruning (§5). More samples find "
		"smaller symmetric parts at the cost of time."));
	parameters.addParam(RichInt(
		"max_working_vertices", o.working.max_vertices, "Working resolution (vertices)",
		"A mesh with more vertices than this is analysed on a copy simplified to about this many by quadric "
		"edge collapse (as Simplification: Quadric Edge Collapse Decimation does); what is found is carried "
		"back to every vertex of the mesh, and the deviation is measured on the mesh itself. The time then "
		"grows with the symmetries found, not with the tessellation. A point cloud with more points is "
		"analysed on about this many of them, spread evenly (as Point Cloud Simplification picks them). "
		"A mesh far coarser than the curvature ball (long thin triangles, as CAD exports have) is analysed on a "
		"copy of the same surface with its long edges split, within this many vertices too. 0 analyses every "
		"mesh at its own resolution, coarse ones refined."));
	parameters.addParam(RichInt(
		"pair_sample_count", o.pair_sample_count, "Paired samples",
		"Number of samples (the paper's random subset P') that are paired against all the others in "
		"signature space (§2.2). Each pair votes for one transformation. 0 (the default) chooses it by the "
		"bound of the paper's Appendix (Equation 1) so that a patch of the minimum patch area is found with 95% "
		"probability, as far as a budget of points in transformation space allows; the log says the number "
		"chosen and whether the bound was met."));
	parameters.addParam(RichPercentage(
		"curvature_radius", o.curvature_radius * d, 0, d, "Curvature radius",
		"Radius of the ball over which curvature and principal directions are estimated at each sample (§2). "
		"It should exceed the noise of the scan and stay below the size of the features that matter."));
	parameters.addParam(RichFloat(
		"umbilic_ratio", o.umbilic_ratio, "Umbilic pruning ratio",
		"The paper's gamma (§2.1), in (0, 1): samples whose principal curvatures satisfy |k1/k2| > gamma "
		"have ill-defined principal directions and are not paired."));
	parameters.addParam(RichFloat(
		"signature_tolerance", o.signature_tolerance, "Signature tolerance",
		"Radius of the range query in signature space (§2.2), dimensionless: two samples are paired only if "
		"their signatures differ by less than this. The signature is the pair of principal curvatures times "
		"the curvature radius, or for similarities the shape index (a scale-free function of k1/k2, in [-1, 1])."));
	parameters.addParam(RichPercentage(
		"cluster_bandwidth", o.cluster_bandwidth * d, 0, d, "Clustering bandwidth",
		"Kernel width h of mean-shift clustering in transformation space (§3.1). Distances in that space "
		"are measured in units of the bounding-box diagonal."));
	parameters.addParam(RichInt(
		"min_cluster_support", o.min_cluster_support, "Minimum cluster support",
		"Clusters in transformation space supported by fewer pairs than this are not verified (§3.1)."));
	parameters.addParam(RichPercentage(
		"verification_tolerance", o.verification_tolerance * d, 0, d, "Verification tolerance",
		"Largest distance between a transformed point and the surface accepted while growing a symmetric "
		"patch (§4). Set it a little above the noise level of the scan."));
	parameters.addParam(RichFloat(
		"min_patch_area", o.min_patch_area * 100.0, "Minimum patch area (%)",
		"Symmetric patches smaller than this percentage of the total surface area are discarded."));
	parameters.addParam(RichInt(
		"max_symmetries", o.max_symmetries, "Maximum number of symmetries",
		"At most this many discrete symmetries are reported, the most significant first. "
		"A continuous family (a surface of revolution, a plane, a sphere) is one report besides "
		"them and takes none of their places; at most this many families are reported too."));
	parameters.addParam(RichBool(
		"refine_with_icp", o.refine_with_icp, "Refine with ICP",
		"Refine each transformation with iterative closest points while its patch grows (§4)."));
	if (groupAndBasis)
		appendBasisParameters(o, d, parameters);
	if (createPatchLayers)
		parameters.addParam(RichBool(
			"create_patch_layers", *createPatchLayers, "Create patch layers",
			"For symmetry k, add the layers symmetry_k_source and symmetry_k_target holding the two patches "
			"it maps onto each other. The current mesh stays the input mesh."));
	parameters.addParam(RichInt(
		"random_seed", int(o.random_seed), "Random seed",
		"Seed of every random choice (sampling, paired subset). The result is a deterministic function of "
		"the mesh, the parameters and this seed, 0 included."));
}

symmetry::DetectionOptions fromRichParameterList(const RichParameterList& p, double diagonal)
{
	symmetry::DetectionOptions o;
	if (p.hasParameter("transformation_group"))
		o.group = symmetry::TransformationGroup(p.getEnum("transformation_group"));
	o.sample_count = p.getInt("sample_count");
	o.working.max_vertices = p.getInt("max_working_vertices");
	o.pair_sample_count = p.getInt("pair_sample_count");
	o.umbilic_ratio = p.getFloat("umbilic_ratio");
	o.signature_tolerance = p.getFloat("signature_tolerance");
	o.min_cluster_support = p.getInt("min_cluster_support");
	o.min_patch_area = p.getFloat("min_patch_area") / 100.0;
	o.max_symmetries = p.getInt("max_symmetries");
	o.refine_with_icp = p.getBool("refine_with_icp");
	if (p.hasParameter("reduce_basis")) {
		o.reduce_basis = p.getBool("reduce_basis");
		o.basis_loop_length = p.getInt("basis_loop_length");
	}
	// Any int is a valid seed; negative ones wrap to distinct unsigned seeds.
	o.random_seed = unsigned(p.getInt("random_seed"));
	if (usableDiagonal(diagonal)) {
		o.curvature_radius = p.getAbsPerc("curvature_radius") / diagonal;
		o.cluster_bandwidth = p.getAbsPerc("cluster_bandwidth") / diagonal;
		o.verification_tolerance = p.getAbsPerc("verification_tolerance") / diagonal;
		if (p.hasParameter("basis_tolerance"))
			o.basis_tolerance = p.getAbsPerc("basis_tolerance") / diagonal;
	}
	return o;
}

bool createPatchLayers(const RichParameterList& p)
{
	return p.getBool("create_patch_layers");
}

}  // namespace symmetry_parameters

namespace symmetry_parameters {

void appendSymmetrizationParameters(const symmetry::SymmetrizationOptions& o, RichParameterList& parameters)
{
	parameters.addParam(RichFloat(
		"strength", o.strength, "Strength",
		"Fraction of the way to the exactly symmetric average each vertex moves in a pass, from 0 (no change) to 1 "
		"(both sides of each detected symmetry meet at their average)."));
	parameters.addParam(RichInt(
		"symmetrization_iterations", o.iterations, "Iterations",
		"Passes of the move, each measured on the surface the previous one left (1 to 100)."));
}

symmetry::SymmetrizationOptions symmetrizationOptions(const RichParameterList& p)
{
	symmetry::SymmetrizationOptions o;
	o.strength = p.getFloat("strength");
	o.iterations = p.getInt("symmetrization_iterations");
	return o;
}

void appendReductionParameters(RichParameterList& parameters)
{
	parameters.addParam(RichBool(
		"create_reconstruction_layer", false, "Create reconstruction layer",
		"Also add the model rebuilt from the reduced mesh and its instances, as the layer "
		"symmetry_reconstruction, to compare with the input."));
	parameters.addParam(RichString(
		"instances_file", "", "Instances file (JSON)",
		"Path of a JSON file to write the instances to: for each, its 4x4 transformation and the faces of the "
		"reduced mesh it copies. Empty: no file (the returned values hold the same)."));
}

bool createReconstructionLayer(const RichParameterList& p)
{
	return p.getBool("create_reconstruction_layer");
}

QString instancesFile(const RichParameterList& p)
{
	return p.getString("instances_file");
}

void appendSegmentationParameters(RichParameterList& parameters)
{
	parameters.addParam(RichBool(
		"create_segment_layers", true, "Create segment layers",
		"For segment k, add the layers segment_k_first and segment_k_second holding the part in either pose."));
}

bool createSegmentLayers(const RichParameterList& p)
{
	return p.getBool("create_segment_layers");
}

}  // namespace symmetry_parameters
