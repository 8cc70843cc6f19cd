//! `relief simulate`.

use crate::args::values::*;
use crate::parse;
use clap::Args;
use relief_shade::mlhm::MlhmPreset;
use std::path::PathBuf;

/// `relief simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// MLHM scene to simulate: the reference simulator's .json (with its .dat) or a .mlhm.
    pub input: PathBuf,
    /// Steps to simulate (1 to 10000000).
    #[arg(long, value_parser = simulation_steps, allow_hyphen_values = true)]
    pub steps: u64,
    /// Scene to write: .json (with a .dat beside it, simulation state included) or .mlhm (the
    /// terrain only).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Seed of the rain's random numbers.
    #[arg(long, default_value = "1")]
    pub seed: u64,
    /// Rain in metres of water per second (0 to 100) [default: the scene's, else 0.07].
    #[arg(long, value_name = "M_PER_S", value_parser = water_rate, allow_hyphen_values = true)]
    pub rain: Option<f32>,
    /// Evaporation in metres of water per second (0 to 100) [default: the scene's, else 0.09].
    #[arg(long, value_name = "M_PER_S", value_parser = water_rate, allow_hyphen_values = true)]
    pub evaporation: Option<f32>,
    /// Time step in seconds (0.001 to 10) [default: the scene's, else 0.15].
    #[arg(long, value_name = "S", value_parser = time_step, allow_hyphen_values = true)]
    pub dt: Option<f32>,
    /// Write the step count, the median step time and the volumes added and removed by
    /// design to this .json file (with --frames, also the median and per-frame rebuild and
    /// render times).
    #[arg(long, value_name = "F.json")]
    pub stats: Option<PathBuf>,
    /// Memory the scene may take, e.g. 512M, 8G (default: half the machine's or cgroup's
    /// memory).
    #[arg(long, value_parser = parse::bytes, allow_hyphen_values = true)]
    pub max_memory: Option<u64>,
    /// With --frames: every K steps, rebuild the MLHM hierarchy and render a frame (1 to
    /// 10000000).
    #[arg(long, value_name = "K", value_parser = render_every, allow_hyphen_values = true)]
    pub render_every: Option<u64>,
    /// With --render-every: the folder the frames are written to as frame-00000.png,
    /// frame-00001.png, ... as flythrough numbers them (created if missing), each stage's
    /// time printed per frame.
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,
    /// With --frames: the frames' quality preset, as in render: low, mid, high or max
    /// [default: low].
    #[arg(long)]
    pub preset: Option<MlhmPreset>,
    /// With --frames: frame size WxH in pixels [default: 1280x720].
    #[arg(long, value_parser = parse::image_size)]
    pub size: Option<(u32, u32)>,
    /// With --frames: the camera looking towards compass AZ degrees from EL degrees above the
    /// horizon, at DISTANCE metres from the terrain's centre, as in render [default: render's
    /// framing, 45,30], fixed over the run.
    #[arg(long, value_name = "AZ,EL[,DISTANCE]", value_parser = parse::view, allow_hyphen_values = true)]
    pub view: Option<parse::ViewAngles>,
    /// Every K steps, write the state so far as OUTPUT.step-N.json (or .mlhm) beside the
    /// output, atomically, removing the previous one (1 to 10000000): a killed run keeps its
    /// work. The final output replaces the last.
    #[arg(long, value_name = "K", value_parser = checkpoint_every, allow_hyphen_values = true)]
    pub checkpoint: Option<u64>,
    /// Diagnostic: check the terrain's invariants after every stage of every step (not only
    /// after every step), so an error names the stage that broke them; a few times slower.
    #[arg(long)]
    pub check_stages: bool,
    /// For the tests of the error path: step N (counted as the scene counts its steps)
    /// reports a broken terrain.
    #[arg(long, value_name = "N", hide = true)]
    pub test_fail_at_step: Option<u64>,
}
