//! What to render and how (`relief render`, `view`, `flythrough`, `mesh`): the scene, the tracer,
//! the camera and the light; and the safety tracer's options.

use super::input::*;
use super::values::*;
use crate::parse;
use clap::Args;
use relief_core::{DVec3, Precision, Surface};
use relief_render::TracerChoice;
use relief_shade::mlhm::MlhmPreset;
use relief_trace::{MlhmBacktrack, SafetyOptions};
use std::path::PathBuf;

/// What to render and how: the scene, the tracer, the camera and the light, shared by
/// `relief render` and `relief view`.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// Input and its placement.
    #[command(flatten)]
    pub input: InputArgs,
    /// Surface to render: boxes (flat-topped texels) or triangles [default: triangles; an MLHM
    /// scene is always boxes, see --mode].
    #[arg(long)]
    pub surface: Option<Surface>,
    /// Tracer: naive, mipmap (both exact, no precomputation) or safety (precomputed safety
    /// shapes for static terrain, triangles only; see --safety), or a safety variant by name
    /// [default: mipmap]. For an MLHM scene (.json or .mlhm): naive or hierarchy [default: hierarchy].
    #[arg(long)]
    pub tracer: Option<TracerChoice>,
    /// How the terrain is drawn. MLHM scenes: boxes, or smooth (the terrain they stand for,
    /// smoothed in all three dimensions over a cube of half-size --sigma) [default: boxes].
    /// Any input: mesh (its material stacks smoothed over --sigma and dual-contoured at the
    /// camera's levels of detail, cells of at most --tau pixels, rasterized; Löffler et al.
    /// 2011), the only mode of a .stacks file.
    #[arg(long, value_parser = parse_mlhm_render_mode)]
    pub mode: Option<MlhmRenderMode>,
    /// MLHM smooth mode: the smoothing radius in metres, the half-size of the cube whose
    /// terrain volume defines the surface (1/64 of a cell to 8 cells) [default: one cell].
    /// Mesh mode: the standard deviation of the Gaussian smoothing the stacks' density, in
    /// metres [default: one cell].
    #[arg(long, value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub sigma: Option<f64>,
    /// Stacks meshes (--mode mesh; relief mesh --lod auto): the largest screen-space size of
    /// a mesh cell in pixels (Löffler et al. 2011, equation 1) [default: 10].
    #[arg(long, value_name = "PX", value_parser = tau_px, allow_hyphen_values = true)]
    pub tau: Option<f64>,
    /// Stacks meshes: the height of a density voxel at the finest level, metres; smaller
    /// voxels keep more of a DEM's relief whose spacing is coarse [default: the spacing].
    #[arg(long, value_name = "M", value_parser = parse::positive_length, allow_hyphen_values = true)]
    pub voxel_height: Option<f64>,
    /// Stacks meshes in relief view and relief flythrough: node meshes a frame makes at most
    /// (all: every node the frame wants). The others are drawn by what the last frame drew
    /// in their place (the node next to other neighbours, a coarser or finer level) until a
    /// later frame meshes them, as Löffler et al. amortise their updates; a camera that stays
    /// put catches up. A still picture is the same either way [default: 40, the paper's].
    #[arg(long, value_name = "N|all", value_parser = node_budget)]
    pub node_budget: Option<NodeBudget>,
    /// MLHM scenes: quality preset (Nilles & Müller 2025, section 5): low (no secondary rays,
    /// no AO), mid (water reflections and refractions with cheap absorption, sun shadows, AO
    /// of radius 1 m), high (expensive absorption, shadows and AO on reflected and refracted
    /// surfaces too) or max (AO of radius 2 m) [default: mid].
    #[arg(long)]
    pub preset: Option<MlhmPreset>,
    /// MLHM scenes, hierarchy tracer: store its bounds as f32 or f16 (half the memory, rounded
    /// outwards so they stay conservative; the same image) [default: f32].
    #[arg(long, value_parser = parse::precision)]
    pub hierarchy_bounds: Option<Precision>,
    /// MLHM scenes, hierarchy tracer: how its traversal climbs back up, by a stack of exit
    /// distances or a miss counter: stack or miss [default: stack].
    #[arg(long)]
    pub backtrack: Option<MlhmBacktrack>,
    /// Safety-shape options.
    #[command(flatten)]
    pub safety: SafetyArgs,
    /// Camera position X,Y,Z in world units, e.g. --eye -100,-150,420; framed automatically
    /// when absent.
    #[arg(long, value_parser = parse::point, requires = "target", group = "placement", allow_hyphen_values = true)]
    pub eye: Option<DVec3>,
    /// Point looked at X,Y,Z (with --eye, or with --view instead of the terrain's centre).
    #[arg(long, value_parser = parse::point, requires = "placement", allow_hyphen_values = true)]
    pub target: Option<DVec3>,
    /// Camera up vector X,Y,Z, with --eye and --target; when it is parallel to the view (a
    /// camera looking straight down or up), north is at the top of the image [default: 0,0,1].
    #[arg(long, value_parser = parse::direction, requires = "eye", allow_hyphen_values = true)]
    pub up: Option<DVec3>,
    /// The camera looking towards compass AZ degrees (clockwise from north: north is +y, east
    /// +x, z is up; -360 to 360) from EL degrees above the horizon (more than 0, up to 90:
    /// straight down, with AZ at the top of the image, so 0,90 is a north-up map), at
    /// DISTANCE metres from the target (default: the framing's, at which the terrain fills the
    /// image). It looks at the terrain's centre, or at --target. Without --view and --eye the
    /// camera is --view 45,30 (from the south-west).
    #[arg(long, value_name = "AZ,EL[,DISTANCE]", value_parser = parse::view, group = "placement", allow_hyphen_values = true)]
    pub view: Option<parse::ViewAngles>,
    /// Orthographic camera: parallel rays along the view, from the plane through the eye
    /// perpendicular to it (the depth is measured from that plane); with --view 0,90 a map
    /// with a fixed ground size per pixel.
    #[arg(long)]
    pub ortho: bool,
    /// With --ortho: the image's height in metres [default: the framing's, at which the
    /// terrain fills the image].
    #[arg(long, value_name = "M", value_parser = parse::ortho_height, allow_hyphen_values = true)]
    pub ortho_height: Option<f64>,
    /// Vertical field of view in degrees (0.01 to 179) of the perspective camera [default:
    /// 45].
    #[arg(long, value_parser = parse::fov, allow_hyphen_values = true)]
    pub fov: Option<f64>,
    /// Image size WxH in pixels (not terrain samples: see --fbm-size).
    #[arg(long, value_parser = parse::image_size, default_value = "1280x720")]
    pub size: (u32, u32),
    /// Sun AZIMUTH,ELEVATION in degrees (azimuth clockwise from north, -360 to 360; elevation
    /// -90 to 90).
    #[arg(long, value_parser = parse::sun, default_value = "315,35", allow_hyphen_values = true)]
    pub sun: (f64, f64),
    /// Do not trace shadow rays.
    #[arg(long)]
    pub no_shadows: bool,
    /// MLHM scenes: leave the preset's ambient occlusion out.
    #[arg(long)]
    pub no_ao: bool,
    /// Colour texture (PNG) draped over the terrain's footprint, top row north.
    #[arg(long)]
    pub texture: Option<PathBuf>,
    /// Colour map of the heights: terrain (the hypsometric ramp, rock on steep slopes),
    /// bathymetry (blues below the sea level, land colours above; see --sea-level), greys, or
    /// the perceptually uniform viridis, cividis and magma [default: terrain].
    #[arg(long, value_name = "NAME", value_parser = colour_map)]
    pub colormap: Option<relief_shade::ColourMap>,
    /// Heights in metres (before --z-scale) at the colour map's two ends, e.g. -500,1500;
    /// heights beyond take the nearer end's colour [default: the terrain's lowest and highest].
    #[arg(long, value_name = "MIN,MAX", value_parser = parse::height_range, allow_hyphen_values = true)]
    pub height_range: Option<(f64, f64)>,
    /// With --colormap bathymetry: the height in metres where water turns to land [default:
    /// 0].
    #[arg(long, value_name = "H", value_parser = parse::height, allow_hyphen_values = true)]
    pub sea_level: Option<f64>,
    /// Normals that light the triangles surface: smooth (interpolated from the heights'
    /// gradients at the samples, as DEM viewers shade) or faceted (each triangle's exact
    /// normal); depth, --normals and shadows stay exact either way. Boxes are always faceted
    /// [default: smooth].
    #[arg(long, value_name = "STYLE")]
    pub shading_normals: Option<relief_shade::NormalStyle>,
    /// Exposure applied before tone mapping (1e-4 to 1e4).
    #[arg(long, default_value = "1", value_parser = parse::exposure, allow_hyphen_values = true)]
    pub exposure: f64,
}

/// `--mode`: how an MLHM scene's columns (or any input's material stacks) are rendered.
pub use relief_render::RenderMode as MlhmRenderMode;

fn parse_mlhm_render_mode(s: &str) -> Result<MlhmRenderMode, String> {
    match s {
        "boxes" => Ok(MlhmRenderMode::Boxes),
        "smooth" => Ok(MlhmRenderMode::Smooth),
        "mesh" => Ok(MlhmRenderMode::Mesh),
        _ => Err(format!("unknown mode '{s}' (expected boxes, smooth or mesh)")),
    }
}

/// Options of the safety tracer (Baboud et al. 2011).
#[derive(Debug, Args)]
pub struct SafetyArgs {
    /// Safety shapes: cyl_all or cyl_ext (cylinders for all rays, or for exterior rays only:
    /// cameras outside the terrain's box), optionally +cone_all (conservative cones), +cone_ext
    /// (exact cones for exterior rays) or +cone_exact (exact cones for all rays).
    /// [default: cyl_all+cone_all]
    #[arg(long)]
    pub safety: Option<SafetyOptions>,
    /// Build the shapes for rays at most this many degrees from horizontal (e.g. -45: views
    /// looking down at least 45 degrees); other views are refused.
    #[arg(long, value_parser = parse::phi_max, allow_hyphen_values = true)]
    pub phi_max: Option<f64>,
    /// One shape per texel for all four ray classes (less memory, slower).
    #[arg(long)]
    pub isotropic: bool,
    /// Clamp safety distances to at least one: faster, small errors at sharp silhouettes.
    #[arg(long)]
    pub positive: bool,
    /// Final test on the view-dependent linear surface instead of the two triangles: faster,
    /// approximate between centerlines.
    #[arg(long)]
    pub linear_surface: bool,
    /// Farthest step, in texels, a shape may allow (1 to 1024) [default: 128].
    #[arg(long, value_name = "TEXELS", value_parser = safety_reach, allow_hyphen_values = true)]
    pub safety_reach: Option<u16>,
    /// Where precomputed shapes are kept [default: $RELIEF_CACHE_DIR, $XDG_CACHE_HOME/relief
    /// or ~/.cache/relief].
    #[arg(long)]
    pub cache_dir: Option<PathBuf>,
    /// Neither read nor write the shape cache.
    #[arg(long)]
    pub no_cache: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn render_modes_parse() {
        assert_eq!(parse_mlhm_render_mode("boxes"), Ok(MlhmRenderMode::Boxes));
        assert_eq!(parse_mlhm_render_mode("smooth"), Ok(MlhmRenderMode::Smooth));
        assert!(parse_mlhm_render_mode("spheres").is_err());
    }
}
