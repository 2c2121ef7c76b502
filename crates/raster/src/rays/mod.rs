//! The rays room: a bounding volume hierarchy over the scene's world-space triangles
//! ([`Bvh`], built once per render and only when a scene asks for rays) and the segment
//! queries exact effects ask of it. It knows nothing of lights, materials or pixels.

mod bvh;

pub(crate) use bvh::Bvh;
