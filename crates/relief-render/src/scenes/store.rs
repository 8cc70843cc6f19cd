//! A tile store (made by `relief tile`) opened for frames: its streamer (cache and loader),
//! the surface drawn, the shading, the frames' error bound and the store's photo, if any.

use super::height_field::{legend_colours, shading};
use crate::error::RenderError;
use crate::options::SceneOptions;
use relief_core::{Aabb, Camera, Surface};
use relief_shade::{
    Albedo, FilteredAlbedo, GBuffer, HeightColourMap, NormalStyle, ShadingNormals, ShadingParams,
    TextureFilter,
};
use relief_tiles::{
    FrameRequest, TextureFrameStats, TextureStore, TextureStreamer, TileStore, TileStreamer,
    TiledTerrain,
};
use std::path::Path;
use std::sync::Arc;

/// A tile store opened for frames.
pub struct StoreScene {
    /// The store's frames.
    pub streamer: TileStreamer,
    /// The surface drawn (default: triangles).
    pub surface: Surface,
    /// The box the surface fills.
    pub bounds: Aabb,
    /// Lights and materials, fitted to the terrain; faceted normals (a frame's params light
    /// it with its tiles' smooth normals where asked, see [`StoreScene::frame_params`]).
    pub params: ShadingParams,
    /// The shading normals asked for (`None`: smooth for triangles, faceted for boxes).
    pub normal_style: Option<NormalStyle>,
    /// The colour map over heights in metres, for a legend; `None` where a texture colours
    /// the terrain (the options' or the store's photo).
    pub colours: Option<HeightColourMap>,
    /// The screen-space error bound asked for, pixels.
    pub max_error_px: f64,
    /// The store's photo with its own cache, and how it is filtered; `None` for a store
    /// without one, or when the options drape another picture.
    pub texture: Option<(TextureStreamer, TextureFilter)>,
}

impl StoreScene {
    /// Opens the store at `path` as `options` say.
    pub fn open(path: &Path, options: &SceneOptions) -> Result<Self, RenderError> {
        let store = TileStore::open(path)?;
        let settings = &options.store;
        let texture = match TextureStore::open(path, store.header())? {
            Some(texture) if options.light.texture.is_none() => Some((
                TextureStreamer::new(texture, settings.texture_cache_bytes)?,
                settings.texture_filter,
            )),
            _ => None,
        };
        let surface = options.surface.unwrap_or(Surface::Triangles);
        let bounds = store.world_bounds(surface);
        // A store holds heights in metres: `--z-scale` does not place it.
        let boxes = store.world_bounds(Surface::Boxes);
        let params = shading(&options.light, &boxes, 1.0)?;
        let normal_style = options.light.shading_normals;
        if normal_style == Some(NormalStyle::Smooth) && surface == Surface::Boxes {
            return Err(RenderError::Unsupported(
                "smooth shading normals are for the triangles surface: boxes are always faceted"
                    .into(),
            ));
        }
        let colours = match texture {
            Some(_) if options.light.colours.given() => {
                return Err(RenderError::Colours(format!(
                    "the tile store {} has a photo, which colours the terrain: a colour map \
                     does not apply",
                    path.display()
                )))
            }
            Some(_) => None,
            None => legend_colours(&options.light, &boxes, 1.0)?,
        };
        let streamer = TileStreamer::new(store, surface, settings.cache_bytes)?;
        let max_error_px = settings.max_error_px;
        Ok(StoreScene {
            streamer,
            surface,
            bounds,
            params,
            normal_style,
            colours,
            max_error_px,
            texture,
        })
    }

    /// Whether the store at `path` has a photo (made by `relief tile --texture`).
    pub fn has_texture(path: &Path) -> Result<bool, RenderError> {
        let store = TileStore::open(path)?;
        Ok(TextureStore::open(path, store.header())?.is_some())
    }

    /// The scene in a few words.
    pub fn describe(&self) -> String {
        let header = self.streamer.store().header();
        format!("{}x{} tile store", header.width, header.height)
    }

    /// The shading of the frame `camera` saw into `gbuffer` over `terrain`: the store's photo,
    /// when it has one, filtered over each pixel's footprint (its tiles loaded for the frame
    /// when it `wait`s, else coarser ones standing in), else the scene's own; lit with the
    /// frame's tiles' smooth normals unless faceted ones are asked ([`StoreScene::normals`]).
    pub fn frame_params(
        &self,
        gbuffer: &GBuffer,
        camera: &Camera,
        terrain: &Arc<TiledTerrain>,
        wait: bool,
    ) -> Result<(ShadingParams, Option<TextureFrameStats>), RenderError> {
        let normals = self.normals(terrain);
        let Some((textures, filter)) = &self.texture else {
            return Ok((ShadingParams { normals, ..self.params.clone() }, None));
        };
        let (frame, stats) = textures.frame(gbuffer, camera, terrain.clone(), *filter, wait)?;
        let params = ShadingParams {
            albedo: Albedo::Filtered(FilteredAlbedo(Arc::new(frame))),
            normals,
            ..self.params.clone()
        };
        Ok((params, Some(stats)))
    }

    /// The normals that light a frame drawn over `terrain`: its tiles' smooth normals for
    /// the `triangles` surface unless faceted ones are asked; faceted for `boxes`.
    pub fn normals(&self, terrain: &Arc<TiledTerrain>) -> ShadingNormals {
        match (self.normal_style, self.surface) {
            (Some(NormalStyle::Faceted), _) | (_, Surface::Boxes) => ShadingNormals::Faceted,
            _ => ShadingNormals::smooth(terrain.clone()),
        }
    }

    /// What a frame asks of the streamer: the error bound, culling only when no shadow rays
    /// are cast (they reach tiles outside the view), and whether to `wait` for the tiles.
    pub fn request(&self, wait: bool) -> FrameRequest {
        FrameRequest { max_error_px: self.max_error_px, cull: !self.params.shadows, wait }
    }
}
