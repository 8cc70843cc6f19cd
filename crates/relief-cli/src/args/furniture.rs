//! Map furniture over a rendered picture (`relief render`): three switches rather than one
//! list, so that each reads on its own in a command line and is refused on its own where the
//! camera does not define it.

use clap::Args;
use relief_render::MapFurniture;

/// What to draw over the picture once it is rendered.
#[derive(Debug, Args)]
pub struct FurnitureArgs {
    /// Draw a legend at the bottom right: a colour bar of --colormap over --height-range, with
    /// round heights in metres.
    #[arg(long)]
    pub legend: bool,
    /// Draw a scale bar at the bottom left: a round length (1, 2 or 5 x 10^k m or km) at the
    /// picture's ground size per pixel. Orthographic cameras only (--ortho): a perspective
    /// picture's scale changes with the distance.
    #[arg(long)]
    pub scale_bar: bool,
    /// Draw a north arrow at the top right, pointing where north runs on the picture at the
    /// point looked at (up on a north-up map, turned on a turned or oblique view).
    #[arg(long)]
    pub north_arrow: bool,
}

impl FurnitureArgs {
    /// The furniture these switches ask for.
    pub fn furniture(&self) -> MapFurniture {
        MapFurniture {
            legend: self.legend,
            scale_bar: self.scale_bar,
            north_arrow: self.north_arrow,
        }
    }
}
