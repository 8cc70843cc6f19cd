//! Map furniture drawn over a finished picture: a legend of the height colour map, a scale
//! bar and a north arrow, where the camera defines them, in a small bitmap font scaled with
//! the picture.

mod canvas;
pub mod font;
pub mod legend;
pub mod north_arrow;
pub mod scale_bar;

use relief_core::Camera;
use relief_shade::HeightColourMap;

use crate::{Picture, RenderError};
use canvas::Canvas;
use scale_bar::ScaleBar;

/// Which furniture to draw over a picture.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MapFurniture {
    /// A colour bar of the height colour map with heights in metres, at the bottom right.
    pub legend: bool,
    /// A round length (1, 2 or 5 x 10^k m or km) at the bottom left; orthographic cameras
    /// only.
    pub scale_bar: bool,
    /// A needle pointing where north runs on the picture, at the top right.
    pub north_arrow: bool,
}

impl MapFurniture {
    /// Whether any furniture is asked for.
    pub fn any(&self) -> bool {
        self.legend || self.scale_bar || self.north_arrow
    }

    /// Refuses, before any rendering, furniture that `camera` and the scene's `colours` (its
    /// height colour map in metres, `None` where materials or a texture colour it) do not
    /// define: a legend without a height colour map, a scale bar but for an orthographic
    /// camera with level rows, a north arrow where north runs along the view.
    pub fn check(
        &self,
        camera: &Camera,
        colours: Option<&HeightColourMap>,
    ) -> Result<(), RenderError> {
        if self.legend && colours.is_none() {
            return Err(RenderError::Furniture(
                "a legend shows a colour map of heights; this picture is coloured by its \
                 materials or a texture"
                    .into(),
            ));
        }
        if self.scale_bar {
            scale_bar::metres_per_pixel(camera)?;
        }
        if self.north_arrow {
            north_arrow::north_on_screen(camera)?;
        }
        Ok(())
    }

    /// Draws the furniture asked for over `picture`, which `camera` took of a scene coloured
    /// by `colours` (see [`MapFurniture::check`], whose errors it gives too).
    pub fn draw(
        &self,
        picture: &mut Picture,
        camera: &Camera,
        colours: Option<&HeightColourMap>,
    ) -> Result<(), RenderError> {
        self.check(camera, colours)?;
        let (width, height) = (picture.width, picture.height);
        let unit = furniture_unit(width, height);
        let mut canvas = Canvas { rgb: &mut picture.rgb, width, height };
        if let (true, Some(colours)) = (self.legend, colours) {
            let top = if self.north_arrow { north_arrow::bottom(unit) } else { 0 };
            legend::draw(&mut canvas, colours, unit, top);
        }
        if self.scale_bar {
            let metres_per_pixel = scale_bar::metres_per_pixel(camera)?;
            let max_pixels = (width as f64 * scale_bar::MAX_WIDTH_FRACTION) as u32;
            scale_bar::draw(&mut canvas, &ScaleBar::choose(metres_per_pixel, max_pixels), unit);
        }
        if self.north_arrow {
            north_arrow::draw(&mut canvas, north_arrow::north_on_screen(camera)?, unit);
        }
        Ok(())
    }
}

/// The furniture's pixel scale for a `width` x `height` picture: one font pixel a picture
/// pixel up to about 400 pixels on the shorter side, then one more every 270 (4 at
/// 1920 x 1080), so that text reads alike at every size.
pub fn furniture_unit(width: u32, height: u32) -> u32 {
    ((width.min(height) as f64 / 270.0).round() as u32).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_unit_grows_with_the_picture() {
        assert_eq!(furniture_unit(480, 270), 1);
        assert_eq!(furniture_unit(640, 360), 1);
        assert_eq!(furniture_unit(1280, 720), 3);
        assert_eq!(furniture_unit(1920, 1080), 4);
        assert_eq!(furniture_unit(16, 9), 1);
    }
}
