//! The rays room: a bounding volume hierarchy over the scene's world-space triangles
//! ([`Bvh`], built once per render and only when a scene asks for rays) and the queries
//! exact effects ask of it: any hit on a segment (shadows) and the closest hit of a ray
//! (reflections and refractions). It knows nothing of lights, materials or pixels.

mod bvh;

pub(crate) use bvh::Bvh;
