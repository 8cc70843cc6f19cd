//! `relief generate`: write synthetic terrains.

pub mod args;

use crate::{applies, input, memory, outputs, progress};
use anyhow::{bail, Context, Result};
use args::{FbmArgs, GenerateCommand, MlhmArgs, StacksGenArgs};
use indicatif::ProgressBar;
use relief_core::{GridGeometry, MaterialStacks, Mlhm, Precision, StackMaterial};
use relief_io::{Format, GeoTiffStripWriter, MlhmScene, ReadOptions};
use relief_sim::{
    carved_scene, rivers_rain, stacks_terrain, CarvedScene, FbmParams, FbmRows,
    StacksTerrainParams, RIVERS_RAIN_SEED,
};
use std::path::Path;
use std::time::Duration;

/// Runs `relief generate fbm`, `relief generate mlhm` or `relief generate stacks`.
pub fn run(command: &GenerateCommand) -> Result<()> {
    match command {
        GenerateCommand::Fbm(args) => run_fbm(args),
        GenerateCommand::Mlhm(args) => run_mlhm(args),
        GenerateCommand::Stacks(args) => run_stacks(args),
    }
}

/// Runs `relief generate fbm`: the terrain in the height format the output's extension names.
fn run_fbm(args: &FbmArgs) -> Result<()> {
    outputs::check_writable(&args.output)?;
    outputs::check_height_file(&args.output, Some((args.size, args.size)))?;
    if relief_io::format_of(&args.output, &ReadOptions::default())? == Format::GeoTiff {
        return stream_fbm_geotiff(args);
    }
    let field = input::fbm(args.size, args.seed, &memory::budget(None))?;
    let notes = relief_io::write_height_field_georeferenced(
        &args.output,
        &field,
        None,
        relief_io::LengthUnit::Metre,
    )?;
    eprintln!(
        "wrote {} ({} x {}, heights {:.1}..{:.1})",
        args.output.display(),
        field.width(),
        field.height(),
        field.min_sample(),
        field.max_sample()
    );
    for note in notes {
        eprintln!("  {note}");
    }
    Ok(())
}

/// Samples computed and written at a time by [`stream_fbm_geotiff`] (16 MiB of f32).
const FBM_BAND_SAMPLES: usize = 1 << 22;

/// `relief generate fbm -o out.tif`: the terrain computed and written a band of rows at a
/// time, never whole in memory, to the very file [`relief_io::write_geotiff`] writes of it.
/// Two passes: the lowest height first (samples start at 0), then the bands, north first.
fn stream_fbm_geotiff(args: &FbmArgs) -> Result<()> {
    let n = args.size;
    let terrain = FbmRows::new(n, n, args.seed, &FbmParams::for_size(n, n))
        .context("generating fBm terrain")?;
    let bar = progress::bar(2 * n as u64, "generating");
    terrain.lowest_with_progress(|rows| bar.set_position(rows as u64));
    let mut out = GeoTiffStripWriter::create(&args.output, n, n, &GridGeometry::unit())?;
    let band = (FBM_BAND_SAMPLES / n).clamp(1, n);
    let mut samples = vec![0f32; band * n];
    let mut highest = f32::NEG_INFINITY;
    let mut end = n;
    while end > 0 {
        let first = end.saturating_sub(band);
        let rows = &mut samples[..(end - first) * n];
        terrain.read_rows(first, rows).context("generating fBm terrain")?;
        highest = rows.iter().copied().fold(highest, f32::max);
        // The file's rows run north first.
        flip_rows(rows, n);
        out.write_rows(rows)?;
        bar.set_position((2 * n - first) as u64);
        end = first;
    }
    out.finish()?;
    bar.finish_and_clear();
    eprintln!("wrote {} ({n} x {n}, heights 0.0..{highest:.1})", args.output.display());
    Ok(())
}

/// Reverses the order of the `width`-sample rows of `samples` in place.
fn flip_rows(samples: &mut [f32], width: usize) {
    let height = samples.len() / width;
    for row in 0..height / 2 {
        let (top, bottom) = samples.split_at_mut((height - 1 - row) * width);
        top[row * width..][..width].swap_with_slice(&mut bottom[..width]);
    }
}

/// The scenes `relief generate mlhm` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MlhmSceneName {
    /// The reference simulator's procedural RiversRain.
    RiversRain,
    /// One of relief's carved scenes.
    Carved(CarvedScene),
}

impl MlhmSceneName {
    /// Parses `rivers-rain` or a carved scene's name; the error lists every name.
    fn parse(name: &str) -> Result<Self> {
        if name.eq_ignore_ascii_case("rivers-rain") {
            return Ok(MlhmSceneName::RiversRain);
        }
        match name.parse() {
            Ok(scene) => Ok(MlhmSceneName::Carved(scene)),
            Err(_) => bail!(
                "unknown scene '{name}': expected rivers-rain, {}",
                CarvedScene::ALL.map(CarvedScene::name).join(", ")
            ),
        }
    }
}

/// Column slots from which writing takes seconds and a spinner is shown (on a terminal).
const LONG_WRITE_SLOTS: usize = 1 << 24;

/// Largest number of layers the scene format's int8 layer counts hold.
const MAX_FILE_LAYERS: usize = 127;

/// Bytes per column slot while a scene is generated and written: the columns (16), a zero
/// simulation state the writer makes (28), and in half precision the rounded copy (16).
fn bytes_per_slot(half: bool) -> u64 {
    16 + 28 + if half { 16 } else { 0 }
}

/// Runs `relief generate mlhm`.
fn run_mlhm(args: &MlhmArgs) -> Result<()> {
    let scene = MlhmSceneName::parse(&args.scene)?;
    if let (MlhmSceneName::Carved(_), Some(_)) = (scene, args.seed) {
        return Err(applies::refuse(
            "--seed",
            "rivers-rain",
            &format!("the {} scene (a fixed shape)", args.scene),
        ));
    }
    mlhm_file_kind(&args.output)?;
    if !(1..=MAX_FILE_LAYERS).contains(&args.max_layers) {
        bail!("--max-layers {} is outside 1..={MAX_FILE_LAYERS}", args.max_layers);
    }
    check_memory(args)?;
    outputs::check_writable(&args.output)?;
    let started = std::time::Instant::now();
    let map = match scene {
        MlhmSceneName::RiversRain => {
            rivers_rain(args.size, args.max_layers, args.seed.unwrap_or(RIVERS_RAIN_SEED))
        }
        MlhmSceneName::Carved(carved) => carved_scene(carved, args.size, args.max_layers),
    }
    .with_context(|| format!("generating the {} scene", args.scene))?;
    let generated = started.elapsed();
    let mut out = MlhmScene::new(map);
    if args.half {
        out.precision = Precision::F16;
    }
    let slots = out.mlhm.raw_columns().len();
    let spinner = (slots >= LONG_WRITE_SLOTS).then(|| {
        let spinner = ProgressBar::new_spinner();
        spinner.set_message(format!("writing {}", args.output.display()));
        spinner.enable_steady_tick(Duration::from_millis(200));
        spinner
    });
    let written = write_mlhm(&args.output, &out);
    if let Some(spinner) = spinner {
        spinner.finish_and_clear();
    }
    written?;
    eprintln!(
        "wrote {} ({} x {} cells of {} m, {}; generated in {:.0} ms)",
        args.output.display(),
        out.mlhm.width(),
        out.mlhm.height(),
        out.mlhm.cell_size(),
        layer_summary(&out.mlhm),
        generated.as_secs_f64() * 1e3
    );
    Ok(())
}

/// The two kinds of file an MLHM is written to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MlhmFileKind {
    /// The reference simulator's scene: a JSON and a `.dat` beside it.
    ReferenceScene,
    /// relief's own `.mlhm` file (a NumPy `.npz` archive).
    Native,
}

/// The kind of MLHM file `path` names by its extension (`.json` or `.mlhm`); anything else
/// is refused.
fn mlhm_file_kind(path: &Path) -> Result<MlhmFileKind> {
    if input::is_reference_scene(path) {
        Ok(MlhmFileKind::ReferenceScene)
    } else if input::is_native_mlhm(path) {
        Ok(MlhmFileKind::Native)
    } else {
        bail!(
            "output {}: an MLHM is written as .mlhm (relief's own file) or .json (the reference \
             simulator's scene, with its .dat beside it)",
            path.display()
        )
    }
}

/// Writes `scene` to `path` in the file its extension names: a `.json` scene (and its
/// `.dat`), or a `.mlhm` file of the scene's map at the scene's precision (no simulation
/// state or other settings).
pub(super) fn write_mlhm(path: &Path, scene: &MlhmScene) -> Result<()> {
    match mlhm_file_kind(path)? {
        MlhmFileKind::ReferenceScene => relief_io::write_mlhm_scene(path, scene)?,
        MlhmFileKind::Native => {
            let map = scene.mlhm.to_precision(scene.precision).context("rounding to f16")?;
            relief_io::write_mlhm_native(path, &map)?;
        }
    }
    Ok(())
}

/// Refuses a size of 0 or one whose scene would not fit the memory budget, before allocating.
fn check_memory(args: &MlhmArgs) -> Result<()> {
    if args.size == 0 {
        bail!("--size 0: a scene needs at least 1 x 1 cells");
    }
    let memory::Budget { bytes: limit, origin } = memory::budget(args.max_memory);
    let cells = (args.size as u128).pow(2);
    let needed = cells * (1 + args.max_layers as u128 * u128::from(bytes_per_slot(args.half)));
    if needed > u128::from(limit) {
        bail!(
            "a {0}x{0} scene with {1} layers needs {2} MiB, over the {3} MiB memory limit ({origin})",
            args.size,
            args.max_layers,
            needed >> 20,
            limit >> 20
        );
    }
    Ok(())
}

/// How many cells hold more than one column, e.g. "12034 cells with 2+ columns, at most 3".
fn layer_summary(map: &Mlhm) -> String {
    let counts = map.layer_counts();
    let layered = counts.iter().filter(|&&n| n >= 2).count();
    let most = counts.iter().copied().max().unwrap_or(0);
    format!("{layered} cells with 2+ columns, at most {most}")
}

/// Bytes per stack while a stacks terrain is generated and written, measured on the paper's
/// 2048 x 4096 terrain with room to spare: the ground and its smoothed copy, the fBm field,
/// the offsets, and the layers (about 1.5 a stack) twice over, built and then as file bytes.
const STACKS_BYTES_PER_STACK: u128 = 80;

/// Stacks from which generating takes seconds and a spinner is shown (on a terminal).
const LONG_STACKS: usize = 1 << 20;

/// Runs `relief generate stacks`.
fn run_stacks(args: &StacksGenArgs) -> Result<()> {
    if !relief_io::is_stacks_path(&args.output) {
        bail!(
            "output {}: a stacks terrain is written as a .{} file",
            args.output.display(),
            relief_io::STACKS_EXTENSION
        );
    }
    let memory::Budget { bytes: limit, origin } = memory::budget(args.max_memory);
    let needed = args.width as u128 * args.height as u128 * STACKS_BYTES_PER_STACK;
    if needed > u128::from(limit) {
        bail!(
            "a {}x{} stacks terrain needs about {} MiB, over the {} MiB memory limit ({origin})",
            args.width,
            args.height,
            needed >> 20,
            limit >> 20
        );
    }
    outputs::check_writable(&args.output)?;
    let params = StacksTerrainParams {
        spacing: args.spacing,
        max_height: args.max_height,
        ..StacksTerrainParams::default()
    };
    let spinner = (args.width * args.height >= LONG_STACKS).then(|| {
        let spinner = ProgressBar::new_spinner();
        spinner.set_message("generating stacks");
        spinner.enable_steady_tick(Duration::from_millis(200));
        spinner
    });
    let started = std::time::Instant::now();
    let generated = stacks_terrain(args.width, args.height, args.seed, &params);
    let elapsed = started.elapsed();
    if let Some(spinner) = &spinner {
        spinner.set_message(format!("writing {}", args.output.display()));
    }
    let written = generated
        .context("generating the stacks terrain")
        .and_then(|stacks| Ok(relief_io::write_stacks(&args.output, &stacks).map(|()| stacks)?));
    if let Some(spinner) = spinner {
        spinner.finish_and_clear();
    }
    let stacks = written?;
    eprintln!(
        "wrote {} ({} x {} stacks of {} m, {}; generated in {:.0} ms)",
        args.output.display(),
        stacks.width(),
        stacks.height(),
        args.spacing,
        stacks_summary(&stacks),
        elapsed.as_secs_f64() * 1e3
    );
    Ok(())
}

/// The layers and features of `stacks`, e.g. "12034567 layers, 120345 stacks with
/// overhangs, heights 0.0..700.1 m".
fn stacks_summary(stacks: &MaterialStacks) -> String {
    let offsets = stacks.offsets();
    let layers = stacks.layers();
    let overhangs = offsets
        .windows(2)
        .filter(|w| {
            layers[w[0] as usize..w[1] as usize]
                .windows(2)
                .any(|p| p[1].start > p[0].end && p[1].material != StackMaterial::WATER)
        })
        .count();
    let (low, high) = stacks.height_range().unwrap_or((0.0, 0.0));
    format!(
        "{} layers, {overhangs} stacks with overhangs, heights {low:.1}..{high:.1} m",
        layers.len()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_names_parse_and_unknown_ones_list_the_choices() {
        assert_eq!(MlhmSceneName::parse("rivers-rain").unwrap(), MlhmSceneName::RiversRain);
        assert_eq!(
            MlhmSceneName::parse("chasm").unwrap(),
            MlhmSceneName::Carved(CarvedScene::Chasm)
        );
        let err = MlhmSceneName::parse("volcano").unwrap_err().to_string();
        assert!(err.contains("rivers-rain, arches, cave, chasm, overhangs, combined"), "{err}");
    }
}
