//! Multi-layered height maps: the reference simulator's scenes (JSON settings and a zlib
//! `.dat`; [`read_mlhm_scene`], [`write_mlhm_scene`]) and relief's own `.mlhm` files (a NumPy
//! `.npz` archive; [`read_mlhm_native`], [`write_mlhm_native`]).

pub(crate) mod native;
pub(crate) mod scene;
pub(crate) mod scene_header;

pub use native::{
    read_mlhm_native, read_mlhm_native_from_bytes, write_mlhm_native, MLHM_NATIVE_VERSION,
};
pub use scene::{
    read_mlhm_scene, read_mlhm_scene_from_bytes, write_mlhm_scene, MlhmScene, SimulationState,
    F16_SLACK, F32_SLACK,
};
pub use scene_header::{parse_mlhm_scene_header, read_mlhm_scene_header, MlhmSceneHeader};
