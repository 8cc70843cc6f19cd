//! `relief generate`: write synthetic terrains.

use super::check_output;
use crate::args::FbmArgs;
use crate::input;
use anyhow::Result;

/// Runs `relief generate fbm`.
pub fn run(args: &FbmArgs) -> Result<()> {
    check_output(&args.output)?;
    let field = input::fbm(args.size, args.seed)?;
    relief_io::write_height_field_npy(&args.output, &field)?;
    eprintln!(
        "wrote {} ({} x {}, heights {:.1}..{:.1})",
        args.output.display(),
        field.width(),
        field.height(),
        field.min_sample(),
        field.max_sample()
    );
    Ok(())
}
