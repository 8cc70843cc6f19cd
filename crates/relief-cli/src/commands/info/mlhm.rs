//! `relief info scene.json|scene.mlhm`: what a multi-layered height map holds and what
//! rendering it costs.

use super::args::InfoArgs;
use crate::memory::MLHM_BYTES_PER_PIXEL;
use crate::{applies, input};
use anyhow::Result;
use relief_core::{Mlhm, Precision};
use relief_trace::MlhmHierarchy;
use std::io::Write;

/// What the columns of an MLHM add up to.
#[derive(Debug, Default, PartialEq)]
struct ColumnSummary {
    /// Cells with 1, 2, ... columns (index 0: one column).
    cells_by_columns: Vec<usize>,
    /// Lowest and highest bedrock top of any column.
    bedrock: (f64, f64),
    /// Highest solid top (bedrock + sand) and water top.
    solid_max: f64,
    water_max: f64,
    /// Thickest sand and deepest water of any column, metres.
    sand_max: f64,
    water_depth_max: f64,
    /// Cells with water in at least one column.
    wet_cells: usize,
    /// Volumes in cubic metres: bedrock above the lowest bedrock top (where relief clips the
    /// solid), sand, water.
    volumes: [f64; 3],
}

/// Sums up the columns of `map`.
fn summarise(map: &Mlhm) -> ColumnSummary {
    let lowest = map.heights().bedrock_min;
    let area = map.cell_size() * map.cell_size();
    let mut s = ColumnSummary {
        cells_by_columns: vec![0; map.max_layers().max(1)],
        bedrock: (f64::INFINITY, f64::NEG_INFINITY),
        solid_max: f64::NEG_INFINITY,
        water_max: f64::NEG_INFINITY,
        ..ColumnSummary::default()
    };
    for y in 0..map.height() {
        for x in 0..map.width() {
            let count = map.layer_count(x, y);
            if let Some(slot) = count.checked_sub(1) {
                s.cells_by_columns[slot] += 1;
            }
            let mut wet = false;
            for k in 0..count {
                let c = map.column(x, y, k);
                let (bedrock, sand, water) = (c.bedrock as f64, c.sand as f64, c.water as f64);
                let floor = (map.floor(x, y, k) as f64).max(lowest);
                s.bedrock = (s.bedrock.0.min(bedrock), s.bedrock.1.max(bedrock));
                s.solid_max = s.solid_max.max(c.solid_top() as f64);
                s.water_max = s.water_max.max(c.water_top() as f64);
                s.sand_max = s.sand_max.max(sand);
                s.water_depth_max = s.water_depth_max.max(water);
                s.volumes[0] += (bedrock - floor).max(0.0) * area;
                s.volumes[1] += sand * area;
                s.volumes[2] += water * area;
                wet |= water > 0.0;
            }
            s.wet_cells += usize::from(wet);
        }
    }
    s
}

/// Runs `relief info` on the MLHM at `args.input`.
pub fn run(args: &InfoArgs) -> Result<()> {
    if args.read.voids.is_some() {
        return Err(applies::refuse("--voids", "height files", "MLHM scenes"));
    }
    applies::check_read_args(&args.read, Some(&args.input))?;
    let scene = input::load_mlhm(&args.input, &args.read)?;
    let map = &scene.mlhm;
    let mut out = std::io::stdout().lock();
    let format = if input::is_native_mlhm(&args.input) {
        "MLHM, relief's .mlhm (an NPZ archive)".to_string()
    } else {
        let state = if scene.simulation.is_some() { "with" } else { "without" };
        format!("MLHM scene, the reference simulator's JSON and .dat ({state} simulation state)")
    };
    let cs = map.cell_size();
    let precision = match map.precision() {
        Precision::F32 => "f32",
        Precision::F16 => "f16",
    };
    writeln!(out, "file:        {}", args.input.display())?;
    writeln!(out, "format:      {format}")?;
    writeln!(
        out,
        "size:        {} x {} cells of {cs} m ({} x {} m), {precision} values",
        map.width(),
        map.height(),
        map.width() as f64 * cs,
        map.height() as f64 * cs
    )?;
    let s = summarise(map);
    let histogram: Vec<String> = s
        .cells_by_columns
        .iter()
        .enumerate()
        .filter(|(_, &n)| n > 0)
        .map(|(k, n)| format!("{n} with {}", k + 1))
        .collect();
    writeln!(
        out,
        "layers:      {} column slots a cell; cells by columns: {}",
        map.max_layers(),
        if histogram.is_empty() { "none".to_string() } else { histogram.join(", ") }
    )?;
    if s.bedrock.0.is_finite() {
        writeln!(
            out,
            "heights:     bedrock tops {:.3} .. {:.3} m, solid top up to {:.3} m, water top up to \
             {:.3} m",
            s.bedrock.0, s.bedrock.1, s.solid_max, s.water_max
        )?;
        writeln!(out, "sand:        up to {:.3} m thick, {:.1} m³", s.sand_max, s.volumes[1])?;
        writeln!(
            out,
            "water:       {} cells wet, up to {:.3} m deep, {:.1} m³",
            s.wet_cells, s.water_depth_max, s.volumes[2]
        )?;
        writeln!(
            out,
            "bedrock:     {:.1} m³ above the lowest bedrock top (where the solid is clipped)",
            s.volumes[0]
        )?;
    }
    if scene.repaired > 0 {
        writeln!(out, "repaired:    {} values moved to close float slack", scene.repaired)?;
    }
    let hierarchy = MlhmHierarchy::build(map).memory_bytes();
    let map_bytes = map.raw_columns().len() * 16 + map.layer_counts().len();
    writeln!(
        out,
        "to render:   about {:.1} MiB for the map and its hierarchy, plus about {MLHM_BYTES_PER_PIXEL} \
         bytes a pixel",
        (map_bytes + hierarchy) as f64 / 1048576.0
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::MlhmColumn;

    #[test]
    fn summary_counts_columns_volumes_and_water() {
        // Two cells of 2 m: one column on the left; an overhang with a pond on the right.
        let inf = f32::INFINITY;
        let mut map = Mlhm::new(2, 1, 2, 2.0).unwrap();
        map.set_cell(0, 0, &[MlhmColumn::new(1.0, 0.5, 0.0, inf)]).unwrap();
        map.set_cell(
            1,
            0,
            &[MlhmColumn::new(2.0, 0.0, 0.0, 3.0), MlhmColumn::new(4.0, 1.0, 0.25, inf)],
        )
        .unwrap();
        let s = summarise(&map);
        assert_eq!(s.cells_by_columns, vec![1, 1]);
        assert_eq!(s.bedrock, (1.0, 4.0));
        assert_eq!((s.solid_max, s.water_max), (5.0, 5.25));
        assert_eq!((s.sand_max, s.water_depth_max, s.wet_cells), (1.0, 0.25, 1));
        // Bedrock above z = 1: 0 + (2 - 1) + (4 - 3) metres, on 4 m² cells.
        assert_eq!(s.volumes, [8.0, 6.0, 1.0]);
    }
}
