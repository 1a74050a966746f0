// A material's maps by slot, in the order glTF names them and the scene's materials keep them:
// bit k of a material's `uv_sets` and entry k of its map tables mean slot k, for raster
// passes (lib/mesh.wgsl) and ray hits (lib/hit_maps.wgsl) alike.

const MAP_BASE_COLOR: u32 = 0u;
const MAP_METALLIC_ROUGHNESS: u32 = 1u;
const MAP_NORMAL: u32 = 2u;
const MAP_EMISSIVE: u32 = 3u;
const MAP_OCCLUSION: u32 = 4u;
