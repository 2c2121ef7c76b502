//! Which objects' back faces setup skips: all of them with `cull_backfaces`, and with
//! `cull_hidden` (the default) those that cannot show.
//!
//! An object's back faces cannot show when its mesh bounds solids wound outward
//! ([`crate::mesh_solid`]) and the eye is outside them: along any view ray the first face
//! met enters a solid and is a front face, so a back face behind it never wins the depth
//! test (a closed sphere's far half, about half of every solid's triangles). The eye is
//! outside when every vertex lies beyond the near plane (the solids' convex hull then does,
//! and the eye does not), which the vertex stage's outcodes already say. The object must
//! also be opaque (a transparent one shows its far side through the near one) and not
//! mirrored (a transform of negative determinant turns its outward faces clockwise on
//! screen). Snapping to the 1/256-pixel grid can fold a sliver at a silhouette so that a
//! back face's depth ties or beats the front one's at a pixel centre; skipping the back face
//! there shows the front surface, which is the exact picture.

use glam::Mat3;

use super::clip::{INVALID, NEAR};
use crate::options::RenderOptions;
use crate::scene::Object;

/// Whether setup skips the back faces of `object`, whose transformed vertices have the
/// outcodes `codes`.
pub(crate) fn skips_back_faces(
    object: &Object,
    codes: &[u8],
    options: &RenderOptions,
    two_sided: bool,
) -> bool {
    options.cull_backfaces || (options.cull_hidden && back_faces_hidden(object, codes, two_sided))
}

/// Whether no back face of `object` can show (module docs). The mesh's test runs once per
/// mesh (kept with it), after the per-frame ones.
fn back_faces_hidden(object: &Object, codes: &[u8], two_sided: bool) -> bool {
    let opaque = object.material().transparency == 0.0
        && object.material_for(true, two_sided).transparency == 0.0;
    let kept_orientation = Mat3::from_mat4(object.transform()).determinant() > 0.0;
    let beyond_near = codes.iter().fold(0u8, |acc, c| acc | c) & (NEAR | INVALID) == 0;
    opaque && kept_orientation && beyond_near && object.mesh().bounds_solids()
}
