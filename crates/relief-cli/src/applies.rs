//! Which options apply to which input: an option that would do nothing is refused, always
//! with the same message, naming the option and what it applies to.

use crate::args::{ReadArgs, SafetyArgs};
use anyhow::anyhow;
use std::path::Path;

/// The error for `option`, which does nothing `here`: it applies to `applies_to` only.
pub fn refuse(option: &str, applies_to: &str, here: &str) -> anyhow::Error {
    anyhow!("{option} applies to {applies_to} only, not to {here}")
}

/// What the input at `path` is, in words for [`refuse`]: "a GeoTIFF (.tif)", ...
pub fn input_kind(path: Option<&Path>) -> String {
    let Some(path) = path else { return "the default fBm terrain".into() };
    match extension(path).as_deref() {
        Some("json") => "an MLHM scene (.json)".into(),
        Some("mlhm") => "an MLHM file (.mlhm)".into(),
        Some("tif" | "tiff") => "a GeoTIFF".into(),
        Some(e) => format!("a .{e} file"),
        None => format!("{} (no extension)", path.display()),
    }
}

/// The lower-case extension of `path`.
pub fn extension(path: &Path) -> Option<String> {
    path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase)
}

/// Refuses the reading options that do nothing for the input at `path` (`None`: the
/// default fBm terrain): `--png-encoding` for anything but a PNG, `--array` for anything but
/// an .npz archive, `--voids` for the generated terrain (which has none), and `--z-unit` for
/// anything but a height file.
pub fn check_read_args(read: &ReadArgs, path: Option<&Path>) -> anyhow::Result<()> {
    let ext = path.and_then(extension);
    let here = || input_kind(path);
    if read.png_encoding.is_some() && ext.as_deref() != Some("png") {
        return Err(refuse("--png-encoding", "PNG input (.png)", &here()));
    }
    if read.array.is_some() && ext.as_deref() != Some("npz") {
        return Err(refuse("--array", "NumPy archives (.npz)", &here()));
    }
    if path.is_none() && read.voids.is_some() {
        return Err(refuse("--voids", "input files", &here()));
    }
    let height_file = !matches!(ext.as_deref(), None | Some("json" | "mlhm" | "stacks"));
    if read.z_unit.is_some() && (path.is_none() || !height_file) {
        return Err(refuse("--z-unit", "height files", &here()));
    }
    Ok(())
}

/// The first safety-shape option given on the command line, if any.
pub fn safety_option_given(args: &SafetyArgs) -> Option<&'static str> {
    [
        (args.safety.is_some(), "--safety"),
        (args.phi_max.is_some(), "--phi-max"),
        (args.isotropic, "--isotropic"),
        (args.positive, "--positive"),
        (args.linear_surface, "--linear-surface"),
        (args.safety_reach.is_some(), "--safety-reach"),
        (args.cache_dir.is_some(), "--cache-dir"),
        (args.no_cache, "--no-cache"),
    ]
    .into_iter()
    .find_map(|(given, name)| given.then_some(name))
}
