#include "filter_texts.h"

namespace symmetry_texts {

namespace {

QString detectionIntro()
{
	return "Finds parts of the surface that are mapped onto other parts by a rotation, reflection, "
	       "translation or uniform scaling, even when the symmetry is only partial (it holds on some "
	       "patches, not on the whole model) and approximate (it holds up to a tolerance).<br>"
	       "Curvature signatures are computed at surface samples; pairs of similar samples vote for the "
	       "transformation that maps one onto the other; mean-shift clustering of the votes in "
	       "transformation space gives candidate symmetries, each verified by growing the pair of patches "
	       "it maps onto each other; finally the symmetries are reduced to a few generators.<br>"
	       "On a point cloud (vertices, no faces) the curvature comes from a fit to the points around each "
	       "sample and the patches grow over each point's nearest neighbours; the cloud's own normals are "
	       "used when every point has one, and estimated otherwise. A cloud of more points than the working "
	       "resolution is analysed on an evenly spread subset of them.<br><br>"
	       "<b>Outputs</b><br>"
	       "<i>Vertex quality</i>: signed deviation from perfect symmetry of each vertex under the most "
	       "significant symmetry it belongs to, as a fraction of the bounding-box diagonal (Figure 1 of "
	       "the paper); 0 where no symmetry holds.<br>"
	       "<i>Vertex colour</i>: a ramp over that deviation, symmetric around 0; grey where no symmetry "
	       "holds.<br>"
	       "<i>Attribute symmetry_id</i> (per vertex, scalar): index of that symmetry, -1 where none "
	       "holds.<br>"
	       "<i>Layers symmetry_k_source and symmetry_k_target</i> (if <i>Create patch layers</i> is on): "
	       "the two patches that symmetry k maps onto each other; the input stays the current mesh.<br>";
}

QString detectionReturnedValues()
{
	return "<i>Returned values</i>: symmetry_count; transforms (16 numbers per symmetry, the row-major 4x4 "
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
	       "simplified copy analysed, or points of a cloud's subset; 0 when the input itself was), point_cloud and normals_estimated (the "
	       "input was a point cloud, whose normals were estimated), welded_vertices (vertices at the same "
	       "position as another, of a triangle soup or of a repeated face, welded on the filter's copy), "
	       "repeated_faces and back_faces (faces dropped on that copy as a repeat of another face over the same "
	       "three positions, the same way round or the other: the back of a double-sided surface), flipped_faces "
	       "(faces turned on that copy to orient each part coherently and outward), noise (estimated, fraction of the "
	       "diagonal), smoothing_radius (presmoothing of a noisy mesh, 0 if none), curvature_radius_used and "
	       "pair_sample_count_used.<br><br>";
}

QString detectionReference()
{
	return "See:<br><i>Niloy J. Mitra, Leonidas J. Guibas, Mark Pauly</i><br>"
	       "<b>\"Partial and Approximate Symmetry Detection for 3D Geometry\"</b><br>"
	       "ACM Transactions on Graphics 25(3) (SIGGRAPH 2006), pages 560-568.";
}

QString symmetrizationIntro()
{
	return "Detects the partial and approximate symmetries of the current mesh (with the parameters of "
	       "<i>Detect Partial and Approximate Symmetries</i>), then moves the vertices of each approximately "
	       "symmetric pair of patches towards their exactly symmetric average: a vertex whose image under the "
	       "symmetry lands off the surface moves so that its image goes half-way (times <i>Strength</i>) to the "
	       "surface, and the other side moves by the same rule under the inverse, so both meet in the middle; "
	       "<i>Iterations</i> passes, each on the surface the previous one left. A vertex moves under the most "
	       "significant symmetry it is in; vertices in no symmetry, and on continuous families (which have "
	       "no single transformation), do not move. An exactly symmetric pair does not move.<br>";
}

QString symmetrizationReturnedValues()
{
	return "<i>Returned values</i>: symmetry_count (symmetries detected), symmetrized_vertices (vertices "
	       "moved), rms_before and rms_after (RMS deviation from perfect symmetry of those vertices, fraction "
	       "of the diagonal, before and after).<br>";
}

QString symmetrizationReference()
{
	return "Symmetrization is named as future work in: <i>Niloy J. Mitra, Leonidas J. Guibas, Mark Pauly</i>, "
	       "<b>\"Partial and Approximate Symmetry Detection for 3D Geometry\"</b>, SIGGRAPH 2006; see also "
	       "Mitra, Guibas, Pauly, \"Symmetrization\", SIGGRAPH 2007.";
}

QString reductionIntro()
{
	return "Detects the partial and approximate symmetries of the current mesh (with the parameters of "
	       "<i>Detect Partial and Approximate Symmetries</i>), then removes the faces that are copies of others "
	       "(Figure 7(c) of the paper): a face of a symmetry's target patch goes when all its points, mapped back "
	       "by the inverse transformation, land within the verification tolerance on faces that stay, or on a "
	       "copy removed before (whose own instance then maps them on back, so one rotation rebuilds a whole "
	       "orbit of blades from one). What stays is the new layer <i>symmetry_reduced</i>, made current; each "
	       "removed copy is rebuilt by an <i>instance</i>: a transformation applied to some faces of the reduced "
	       "mesh. Continuous families (surfaces of revolution, planes) have no finite set of copies and are "
	       "left whole. The input mesh is not changed.<br>"
	       "<i>Layer symmetry_reconstruction</i> (if <i>Create reconstruction layer</i> is on): the reduced mesh "
	       "with every instance applied, to compare with the input.<br>"
	       "<i>Instances file</i> (if a path is given): JSON with input_faces, reduced_faces, size_ratio, "
	       "reconstruction_error and, per instance, symmetries (the detected symmetries composed, as in basis_words: k+1 is symmetry k, -(k+1) its inverse), "
	       "transform (row-major 4x4), faces (indices into the reduced mesh's faces) and removed_faces.<br>";
}

QString reductionReturnedValues()
{
	return "<i>Returned values</i>: symmetry_count (symmetries detected), reduced_faces, size_ratio (reduced faces "
	       "over input faces), instance_count, instance_transforms (16 numbers per instance, row-major 4x4), "
	       "instance_face_counts and instance_faces (the reduced mesh's faces each instance copies, concatenated), "
	       "instance_removed_faces (input faces each stands for), reconstruction_error (largest distance either "
	       "way between the input and its reconstruction, fraction of the diagonal), reduced_layer_id and "
	       "reconstruction_layer_id (-1 without that layer).<br>";
}

QString reductionReference()
{
	return "Symmetry-based reduction is one of the uses of the symmetry graph in: <i>Niloy J. Mitra, Leonidas J. "
	       "Guibas, Mark Pauly</i>, <b>\"Partial and Approximate Symmetry Detection for 3D Geometry\"</b>, "
	       "SIGGRAPH 2006, Section 5 and Figure 7(c).";
}

QString editingIntro()
{
	return "Carries an edit made on one copy to every copy a detected symmetry relates it to (Figure 7(d) of the "
	       "paper). The current mesh is the edited one: a copy of <i>Original mesh</i> with the same vertices and "
	       "faces, some vertices moved. The symmetries are detected on the original (with the parameters of "
	       "<i>Detect Partial and Approximate Symmetries</i>); each vertex of a symmetric copy that maps back onto "
	       "the edited part receives the displacement there, turned by the symmetry (rotated, mirrored, scaled), "
	       "and passes repeat so that an edit travels along a row of copies. The vertices you moved keep their "
	       "position; the original mesh is not changed.<br>";
}

QString editingReturnedValues()
{
	return "<i>Returned values</i>: symmetry_count (symmetries detected on the original), edited_vertices "
	       "(vertices you moved), carried_vertices (vertices that received the edit), passes.<br>";
}

QString segmentationIntro()
{
	return "Finds the parts of a shape that moved rigidly between two poses (Figure 8 of the paper): samples of "
	       "<i>First pose</i> are paired only with samples of <i>Second pose</i> whose curvatures agree, each pair "
	       "votes for the rotation and translation between them, and every cluster of votes that region growing "
	       "verifies is a rigid part. Both meshes get a colour per part (grey where no part holds, e.g. around "
	       "bending joints) and the per-vertex attribute <i>segment_id</i> (-1 where none). The parameters are those "
	       "of <i>Detect Partial and Approximate Symmetries</i>, with lengths in percent of the first pose's "
	       "diagonal and areas in percent of its area; the group is always rotations and translations.<br>"
	       "<i>Layers segment_k_first and segment_k_second</i> (if <i>Create segment layers</i> is on): part k in "
	       "either pose.<br>";
}

QString segmentationReturnedValues()
{
	return "<i>Returned values</i>: segment_count, segment_transforms (16 numbers per segment, row-major 4x4, "
	       "mapping the part in the first pose onto the second), segment_first_vertex_counts and "
	       "segment_second_vertex_counts, segment_rms_errors (fraction of the first pose's diagonal), "
	       "first_labelled_share and second_labelled_share (fraction of each mesh's vertices in some part), "
	       "segment_layer_ids (two per segment, -1 without layers).<br>";
}

}  // namespace

QString detectionName()
{
	return "Detect Partial and Approximate Symmetries";
}

QString symmetrizationName()
{
	return "Symmetrize Approximate Symmetries";
}

QString reductionName()
{
	return "Symmetry-Based Reduction";
}

QString editingName()
{
	return "Carry an Edit to Symmetric Copies";
}

QString segmentationName()
{
	return "Segment Rigid Parts Between Two Poses";
}

QString detectionInfo(bool returnsValues)
{
	return detectionIntro() + (returnsValues ? detectionReturnedValues() : QString()) + detectionReference();
}

QString symmetrizationInfo(bool returnsValues)
{
	return symmetrizationIntro() + (returnsValues ? symmetrizationReturnedValues() : QString()) +
	       symmetrizationReference();
}

QString reductionInfo(bool returnsValues)
{
	return reductionIntro() + (returnsValues ? reductionReturnedValues() : QString()) + reductionReference();
}

QString editingInfo(bool returnsValues)
{
	return editingIntro() + (returnsValues ? editingReturnedValues() : QString()) +
	       "Consistent editing is one of the uses of the symmetry graph in: <i>Niloy J. Mitra, Leonidas J. Guibas, "
	       "Mark Pauly</i>, <b>\"Partial and Approximate Symmetry Detection for 3D Geometry\"</b>, SIGGRAPH 2006, "
	       "Section 5 and Figure 7(d).";
}

QString segmentationInfo(bool returnsValues)
{
	return segmentationIntro() + (returnsValues ? segmentationReturnedValues() : QString()) +
	       "Rigid segmentation between two poses is one of the uses in: <i>Niloy J. Mitra, Leonidas J. Guibas, Mark "
	       "Pauly</i>, <b>\"Partial and Approximate Symmetry Detection for 3D Geometry\"</b>, SIGGRAPH 2006, "
	       "Section 5 and Figure 8.";
}

}  // namespace symmetry_texts
