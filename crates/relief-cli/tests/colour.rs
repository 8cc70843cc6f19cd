//! Colour maps and map furniture end to end: `relief render --colormap` on real bathymetry,
//! the default picture unchanged, and the legend, scale bar and north arrow drawn where asked,
//! the bar as long as its length at the camera's ground size per pixel, the arrow pointing
//! north.

mod common;

use common::{assert_refused, read_f32_npy, relief, scratch};
use std::path::PathBuf;

/// The crop of NOAA's topography/bathymetry grid in the project's data (64 x 48, row 0 south).
fn topobathy() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/topobathy-crop.npy")
}

/// A decoded RGB picture.
struct Rgb {
    width: usize,
    height: usize,
    pixels: Vec<[u8; 3]>,
}

impl Rgb {
    fn at(&self, x: usize, y: usize) -> [u8; 3] {
        self.pixels[y * self.width + x]
    }
}

/// Runs `relief render` with `args` into a scratch PNG named `name`; must succeed.
fn render(name: &str, args: &[&str]) -> Rgb {
    let png = scratch(&format!("{name}.png"));
    let mut all = vec!["render"];
    all.extend(args);
    all.extend(["-o", png.to_str().unwrap()]);
    let out = relief(&all);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let pixels = buf[..info.buffer_size()].chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Rgb { width: info.width as usize, height: info.height as usize, pixels }
}

/// A north-up map of the fBm terrain, `extra` options added, 320 x 180 pixels.
fn map(name: &str, extra: &[&str]) -> Rgb {
    let mut args = vec!["--fbm-size", "64", "--seed", "5", "--view", "0,90", "--ortho"];
    args.extend(["--size", "320x180"]);
    args.extend(extra);
    render(name, &args)
}

/// Which quarters of the picture (top-left, top-right, bottom-left, bottom-right) differ
/// between `a` and `b`.
fn changed_quarters(a: &Rgb, b: &Rgb) -> [bool; 4] {
    let mut changed = [false; 4];
    for y in 0..a.height {
        for x in 0..a.width {
            if a.at(x, y) != b.at(x, y) {
                changed[usize::from(y >= a.height / 2) * 2 + usize::from(x >= a.width / 2)] = true;
            }
        }
    }
    changed
}

#[test]
fn bathymetry_is_blue_below_the_sea_and_land_coloured_above() {
    let (shape, heights) = read_f32_npy(&topobathy());
    assert_eq!(shape, vec![48, 64]);
    // One pixel a sample: an orthographic map straight down over the 64 x 48 samples, spaced
    // 2440 m both ways (about the grid's 2450 x 2430 m), 64 x 48 pixels; pixel (i, j) sees
    // sample (column i, row 47 - j) at its centre.
    let (dx, w, h) = (2440.0, 64.0, 48.0);
    let eye = format!("{},{},50000", w / 2.0 * dx, h / 2.0 * dx);
    let target = format!("{},{},0", w / 2.0 * dx, h / 2.0 * dx);
    let picture = render(
        "bathymetry-64",
        &[
            topobathy().to_str().unwrap(),
            "--spacing",
            "2440",
            "--eye",
            &eye,
            "--target",
            &target,
            "--up",
            "0,1,0",
            "--ortho",
            "--ortho-height",
            &format!("{}", h * dx),
            "--size",
            "64x48",
            "--colormap",
            "bathymetry",
            "--no-shadows",
        ],
    );
    let (mut sea, mut land, mut wrong) = (0, 0, Vec::new());
    for j in 0..48 {
        for i in 0..64 {
            let z = heights[(47 - j) * 64 + i];
            let [r, g, b] = picture.at(i, j);
            let blue = b > r && b > g;
            if z < -20.0 {
                sea += 1;
                if !blue {
                    wrong.push((i, j, z, [r, g, b]));
                }
            } else if z > 20.0 {
                land += 1;
                if blue {
                    wrong.push((i, j, z, [r, g, b]));
                }
            }
        }
    }
    assert!(sea > 500 && land > 500, "{sea} sea and {land} land samples");
    assert!(wrong.len() * 100 <= sea + land, "{} of {} wrong: {wrong:?}", wrong.len(), sea + land);
}

#[test]
fn the_default_picture_is_the_terrain_map() {
    let plain = map("plain", &[]);
    let terrain = map("terrain", &["--colormap", "terrain"]);
    assert!(plain.pixels == terrain.pixels, "--colormap terrain is the default");
    let viridis = map("viridis", &["--colormap", "viridis"]);
    assert!(plain.pixels != viridis.pixels);
}

#[test]
fn furniture_is_drawn_in_its_own_corner() {
    let plain = map("furniture-plain", &["--colormap", "magma"]);
    let legend = map("furniture-legend", &["--colormap", "magma", "--legend"]);
    assert_eq!(changed_quarters(&plain, &legend), [false, false, false, true], "bottom right");
    let bar = map("furniture-bar", &["--colormap", "magma", "--scale-bar"]);
    assert_eq!(changed_quarters(&plain, &bar), [false, false, true, false], "bottom left");
    let arrow = map("furniture-arrow", &["--colormap", "magma", "--north-arrow"]);
    assert_eq!(changed_quarters(&plain, &arrow), [false, true, false, false], "top right");
}

#[test]
fn a_scale_bar_of_l_metres_spans_l_over_the_metres_per_pixel() {
    // 2000 m over 360 rows: 5.56 m a pixel; the bar at most a quarter of 640 pixels (889 m)
    // is 500 m, 90 pixels.
    let picture = render(
        "scale",
        &["--fbm-size", "64", "--view", "0,90", "--ortho", "--ortho-height", "2000"]
            .into_iter()
            .chain(["--size", "640x360", "--scale-bar"])
            .collect::<Vec<_>>(),
    );
    let mut longest = 0;
    for y in picture.height / 2..picture.height {
        let mut run = 0;
        for x in 0..picture.width / 2 {
            run = if picture.at(x, y) == [0, 0, 0] { run + 1 } else { 0 };
            longest = longest.max(run);
        }
    }
    let want = 500.0 / (2000.0 / 360.0);
    assert!((longest as f64 - want).abs() <= 1.0, "the bar is {longest} px, not {want}");
}

/// The centre of the pixels of `colour` in the top-right quarter of `picture`.
fn centroid(picture: &Rgb, colour: [u8; 3]) -> (f64, f64) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in 0..picture.height / 2 {
        for x in picture.width / 2..picture.width {
            if picture.at(x, y) == colour {
                (sx, sy, n) = (sx + x as f64, sy + y as f64, n + 1.0);
            }
        }
    }
    assert!(n > 10.0, "no needle of {colour:?}");
    (sx / n, sy / n)
}

/// The direction of the north arrow's red half from its grey half, pixel axes (y down).
fn arrow_direction(picture: &Rgb) -> (f64, f64) {
    let (north, south) = (centroid(picture, [200, 30, 30]), centroid(picture, [96, 96, 96]));
    let (dx, dy) = (north.0 - south.0, north.1 - south.1);
    let length = dx.hypot(dy);
    (dx / length, dy / length)
}

#[test]
fn the_north_arrow_points_north() {
    let up = arrow_direction(&map("north-up", &["--north-arrow"]));
    assert!(up.1 < -0.99, "a north-up map's arrow points up: {up:?}");
    // East at the top of the picture: north is to the left.
    let turned = render(
        "north-east-up",
        &["--fbm-size", "64", "--view", "90,90", "--ortho", "--size", "320x180", "--north-arrow"],
    );
    let left = arrow_direction(&turned);
    assert!(left.0 < -0.99, "with east up the arrow points left: {left:?}");
    // Looking north-east: north is up and to the left.
    let oblique = render(
        "north-oblique",
        &["--fbm-size", "64", "--view", "45,30", "--size", "320x180", "--north-arrow"],
    );
    let d = arrow_direction(&oblique);
    assert!(d.0 < -0.3 && d.1 < -0.3, "looking north-east, north is up-left: {d:?}");
}

#[test]
fn furniture_the_camera_does_not_define_is_refused() {
    let png = scratch("refused.png");
    let out = relief(&["render", "--scale-bar", "-o", png.to_str().unwrap()]);
    assert_refused(&out, "a scale bar needs an orthographic camera (--ortho)");
    assert!(!png.exists(), "nothing rendered");
    let out = relief(&["render", "--colormap", "jet", "-o", png.to_str().unwrap()]);
    assert_refused(&out, "known: terrain, bathymetry, greys, viridis, cividis, magma");
    assert_eq!(String::from_utf8_lossy(&out.stderr).lines().count(), 1);
}
