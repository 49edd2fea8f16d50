//! Loading: the files a render scene names (meshes, textures) and preparing a scene in the
//! background.

pub mod assets;
pub mod scene_load;
