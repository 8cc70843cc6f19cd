//! The value parsers of the arguments: whole numbers and numbers held to their ranges.

use crate::parse;

/// A colour map by name; the message lists the known names.
pub(crate) fn colour_map(s: &str) -> Result<relief_shade::ColourMap, String> {
    relief_shade::ColourMap::from_name(s).map_err(|_| {
        format!("unknown colour map '{s}' (known: {})", relief_shade::ColourMap::known_names())
    })
}

pub(crate) fn tau_px(s: &str) -> Result<f64, String> {
    parse::number_in(s, "a number of pixels", &(0.01..=1e4))
}

/// `--node-budget`: node meshes a frame makes at most; `None`: all.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeBudget(pub Option<usize>);

/// `--node-budget`: 1 to 1000000 nodes, or `all`.
pub(crate) fn node_budget(s: &str) -> Result<NodeBudget, String> {
    if s == "all" {
        return Ok(NodeBudget(None));
    }
    parse::whole_in(s, 1..=1_000_000, "node budget").map(|n| NodeBudget(Some(n as usize)))
}

pub(crate) fn non_negative_number(s: &str) -> Result<f64, String> {
    parse::number_in(s, "a number of pixels", &(0.0..=1e6))
}

pub(crate) fn cache_mb(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 16..=(1 << 24), "megabytes of cache")
}

pub(crate) fn tile_samples(s: &str) -> Result<u32, String> {
    parse::whole_in(s, 16..=4096, "samples per tile side").map(|v| v as u32)
}

/// `--cell`: 2 to 4096 samples.
pub(crate) fn cell_samples(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 2..=4096, "cell").map(|v| v as usize)
}

/// `--lop`: 2 to 10 levels.
pub(crate) fn lop_levels(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 2..=10, "number of levels of precision").map(|v| v as usize)
}

/// A finite number above 0.
pub(crate) fn positive_number(s: &str) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|_| format!("'{s}' is not a number"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{s} must be a finite number above 0"))
    }
}

/// A sun's angular radius: 0 to 45 degrees.
pub(crate) fn sun_radius(s: &str) -> Result<f64, String> {
    parse::number_in(s, "sun radius", &(0.0..=relief_shade::shade_map::MAX_SUN_RADIUS_DEG))
        .map_err(|e| format!("{e} degrees"))
}

/// Rays per sample of a shade map: 1 to 4096.
pub(crate) fn shade_rays(s: &str) -> Result<u32, String> {
    let max = u64::from(relief_shade::shade_map::MAX_RAYS_PER_SAMPLE);
    parse::whole_in(s, 1..=max, "ray count").map(|n| n as u32)
}

/// Directions of a horizon map: 1 to 4096.
pub(crate) fn azimuths(s: &str) -> Result<u32, String> {
    let max = u64::from(relief_shade::horizon::MAX_AZIMUTHS);
    parse::whole_in(s, 1..=max, "number of directions").map(|n| n as u32)
}

/// An observer's height above the ground: 0 to 10000 metres.
pub(crate) fn observer_height(s: &str) -> Result<f64, String> {
    parse::number_in(s, "observer height", &(0.0..=1e4)).map_err(|e| format!("{e} metres"))
}

/// A search radius: above 0, at most 1e8 metres.
pub(crate) fn radius(s: &str) -> Result<f64, String> {
    let r = parse::number_in(s, "radius", &(0.0..=1e8)).map_err(|e| format!("{e} metres"))?;
    if r > 0.0 {
        Ok(r)
    } else {
        Err(format!("radius {s} is not above 0 metres"))
    }
}

/// An atmospheric refraction coefficient: 0 to 0.99.
pub(crate) fn refraction(s: &str) -> Result<f64, String> {
    parse::number_in(s, "refraction coefficient", &(0.0..=0.99))
}

/// A terrain's samples (or an MLHM's cells) per side: 1 to 65536.
pub(crate) fn terrain_side(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 1..=65536, "size").map(|v| v as usize)
}

/// A seed: any whole number from 0 to 2^64 - 1.
pub(crate) fn seed(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 0..=u64::MAX, "seed")
}

/// `--safety-reach`: 1 to 1024 texels (the precomputation's time grows with it).
pub(crate) fn safety_reach(s: &str) -> Result<u16, String> {
    parse::whole_in(s, 1..=1024, "--safety-reach").map(|v| v as u16)
}

/// `--max-layers`: 1 to 127, what the scene format's int8 layer counts hold.
pub(crate) fn max_layers(s: &str) -> Result<usize, String> {
    parse::whole_in(s, 1..=127, "--max-layers").map(|v| v as usize)
}

/// `--frames`: 1 to 100000 frames.
pub(crate) fn frames(s: &str) -> Result<u32, String> {
    parse::whole_in(s, 1..=100_000, "--frames").map(|v| v as u32)
}

/// `--frame-budget`: 5 to 1000 milliseconds.
pub(crate) fn frame_budget(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 5..=1000, "--frame-budget")
}

/// `--repeat`: 1 to 1000 runs of every view.
pub(crate) fn repeat(s: &str) -> Result<u32, String> {
    parse::whole_in(s, 1..=1000, "--repeat").map(|v| v as u32)
}

/// `--checkpoint`: 1 to 10^7 steps.
pub(crate) fn checkpoint_every(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 1..=10_000_000, "--checkpoint")
}

/// `--render-every`: 1 to 10^7 steps.
pub(crate) fn render_every(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 1..=10_000_000, "--render-every")
}

/// Simulation steps: 1 to 10^7.
pub(crate) fn simulation_steps(s: &str) -> Result<u64, String> {
    parse::whole_in(s, 1..=10_000_000, "step count")
}

/// A rate of rain or evaporation: 0 to 100 m/s.
pub(crate) fn water_rate(s: &str) -> Result<f32, String> {
    parse::number_in(s, "water rate", &(0.0..=100.0))
        .map(|v| v as f32)
        .map_err(|e| format!("{e} m/s"))
}

/// A time step: 0.001 to 10 s.
pub(crate) fn time_step(s: &str) -> Result<f32, String> {
    parse::number_in(s, "time step", &(0.001..=10.0))
        .map(|v| v as f32)
        .map_err(|e| format!("{e} s"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_numbers_are_held_to_their_ranges() {
        assert_eq!(terrain_side("65536"), Ok(65536));
        assert!(terrain_side("0").is_err() && terrain_side("-4").is_err());
        assert_eq!(seed("18446744073709551615"), Ok(u64::MAX));
        assert!(safety_reach("1025").is_err() && max_layers("128").is_err());
    }
}
