//! Golden images: every `tests/golden/<name>.args` is a case, compared with the reference
//! picture `tests/golden/<name>.png` beside it, with a tolerance.
//!
//! A case file holds `relief` commands, one a line (`#` starts a comment line; arguments are
//! separated by white space). The lines before the last make the inputs (say
//! `generate mlhm ...`); the last renders, and gets `-o <picture>` appended. In the arguments,
//! `{scratch}` is a folder of the case's own, and `{shared}` the project's shared folder
//! (../shared beside the repository): a case that names it is reported ignored in a bare
//! clone, as relief-io's `tests/common/clients.rs` reports tests reading the shared data.
//!
//! To add a case, write its `.args` file and run the test: a case without a reference picture
//! writes it and fails, saying so, so that the new picture is looked at before it is
//! committed. After an intended change of the pictures, rewrite them all with
//! `RELIEF_BLESS=1 cargo test -p relief-cli --test golden`.

mod common;

use common::{clients, shared_data};
use libtest_mimic::{Completion, Failed, Trial};
use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    let folder = golden_folder();
    let mut trials: Vec<Trial> = cases(&folder).into_iter().map(case_trial).collect();
    trials.push(Trial::test("every_reference_picture_has_its_case", || {
        every_reference_picture_has_its_case(&golden_folder())
    }));
    trials.push(Trial::test("a_case_without_a_reference_writes_it_and_fails", || {
        a_case_without_a_reference_writes_it_and_fails()
    }));
    clients::run(trials);
}

/// `tests/golden` of this crate.
fn golden_folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// One golden case: its name, its commands (each a list of arguments) and the folder of its
/// case file and reference picture.
#[derive(Debug, Clone)]
struct Case {
    name: String,
    commands: Vec<Vec<String>>,
    folder: PathBuf,
}

/// Every `*.args` case in `folder`, by name.
fn cases(folder: &Path) -> Vec<Case> {
    let mut cases: Vec<Case> = std::fs::read_dir(folder)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", folder.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "args"))
        .map(|path| read_case(&path))
        .collect();
    cases.sort_by(|a, b| a.name.cmp(&b.name));
    cases
}

/// The case in the file at `path`.
fn read_case(path: &Path) -> Case {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let commands = text
        .lines()
        .map(str::trim)
        .filter(|line| !line.is_empty() && !line.starts_with('#'))
        .map(|line| line.split_whitespace().map(String::from).collect())
        .collect();
    Case {
        name: path.file_stem().unwrap().to_string_lossy().into_owned(),
        commands,
        folder: path.parent().unwrap().to_path_buf(),
    }
}

impl Case {
    /// The reference picture.
    fn reference(&self) -> PathBuf {
        self.folder.join(format!("{}.png", self.name))
    }

    /// The files of the shared folder the case reads (`{shared}/...`), relative to it.
    fn shared_files(&self) -> Vec<String> {
        let arguments = self.commands.iter().flatten();
        arguments.filter_map(|a| a.strip_prefix("{shared}/").map(String::from)).collect()
    }

    /// Runs the commands and compares the picture with the reference (writes the reference
    /// when it is missing, or every time with `RELIEF_BLESS` set); `Err` says why it failed.
    fn run(&self) -> Result<(), String> {
        let (last, setup) = self.commands.split_last().ok_or("the case has no command")?;
        let scratch = std::env::temp_dir()
            .join(format!("relief-golden-{}", std::process::id()))
            .join(&self.name);
        std::fs::create_dir_all(&scratch).map_err(|e| e.to_string())?;
        let picture = scratch.join("picture.png");
        for command in setup {
            self.relief(command, &scratch, None)?;
        }
        self.relief(last, &scratch, Some(&picture))?;
        let reference = self.reference();
        let bless = std::env::var_os("RELIEF_BLESS").is_some();
        if bless || !reference.is_file() {
            std::fs::copy(&picture, &reference).map_err(|e| e.to_string())?;
            if bless {
                eprintln!("blessed {}", reference.display());
                return Ok(());
            }
            return Err(format!(
                "no reference picture: wrote {}; look at it, and commit it if it is right",
                reference.display()
            ));
        }
        compare(&picture, &reference)
    }

    /// Runs `relief` with `arguments` (placeholders replaced) and `-o output` when given.
    fn relief(
        &self,
        arguments: &[String],
        scratch: &Path,
        output: Option<&Path>,
    ) -> Result<(), String> {
        let mut args: Vec<String> = Vec::new();
        for a in arguments {
            args.push(match a.strip_prefix("{shared}/") {
                Some(relative) => match shared_data(relative) {
                    Some(path) => path.to_string_lossy().into_owned(),
                    None => return Err(format!("{relative} is not in the shared folder")),
                },
                None => a.replace("{scratch}", &scratch.to_string_lossy()),
            });
        }
        let mut command = Command::new(env!("CARGO_BIN_EXE_relief"));
        command.args(&args);
        if let Some(output) = output {
            command.arg("-o").arg(output);
        }
        let out = command.output().map_err(|e| e.to_string())?;
        if !out.status.success() {
            return Err(format!(
                "relief {} failed: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        Ok(())
    }
}

/// The trial of `case`: ignored, with the reason, where it reads the shared folder and that is
/// absent (a bare clone) and `RELIEF_REQUIRE_SHARED_DATA` is not 1.
fn case_trial(case: Case) -> Trial {
    Trial::ignorable_test(case.name.clone(), move || {
        let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
        let required = std::env::var("RELIEF_REQUIRE_SHARED_DATA").as_deref() == Ok("1");
        if let Some(relative) = case.shared_files().first() {
            if !shared.join(relative).is_file() && !shared.is_dir() && !required {
                return Ok(Completion::ignored_with(format!(
                    "{}: ../shared, which holds {relative}, is not beside the repository",
                    clients::SHARED_MISSING
                )));
            }
        }
        case.run().map(|()| Completion::Completed).map_err(Failed::from)
    })
}

fn decode(path: &Path) -> Result<(u32, u32, Vec<u8>), String> {
    let file = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("PNG too large")?];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    buf.truncate(info.buffer_size());
    Ok((info.width, info.height, buf))
}

/// Compares `picture` with `reference`: the same size, a mean difference of at most half a
/// level and none above 16 levels.
fn compare(picture: &Path, reference: &Path) -> Result<(), String> {
    let (w, h, got) = decode(picture)?;
    let (gw, gh, want) = decode(reference)?;
    if (w, h) != (gw, gh) {
        return Err(format!("the picture is {w} x {h}, {} is {gw} x {gh}", reference.display()));
    }
    let diffs: Vec<u32> = got.iter().zip(&want).map(|(a, b)| a.abs_diff(*b) as u32).collect();
    let mean = diffs.iter().sum::<u32>() as f64 / diffs.len() as f64;
    let max = diffs.iter().copied().max().unwrap_or(0);
    if mean <= 0.5 && max <= 16 {
        return Ok(());
    }
    Err(format!(
        "image differs from {}: mean {mean:.2}, max {max} levels (RELIEF_BLESS=1 to regenerate)",
        reference.display()
    ))
}

/// Every reference picture in `folder` is some case's: none is left behind by a renamed or
/// deleted case.
fn every_reference_picture_has_its_case(folder: &Path) -> Result<(), Failed> {
    let names: Vec<String> = cases(folder).into_iter().map(|c| c.name).collect();
    let mut orphans = Vec::new();
    for entry in std::fs::read_dir(folder).map_err(|e| e.to_string())? {
        let path = entry.map_err(|e| e.to_string())?.path();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        if path.extension().is_some_and(|e| e == "png") && !names.contains(&stem) {
            orphans.push(path.display().to_string());
        }
    }
    if names.is_empty() || !orphans.is_empty() {
        return Err(format!("{} cases; pictures without a case: {orphans:?}", names.len()).into());
    }
    Ok(())
}

/// A new case (the default pipeline's, in a folder of its own) writes its reference picture
/// and fails saying so; run again, it passes against it.
fn a_case_without_a_reference_writes_it_and_fails() -> Result<(), Failed> {
    if std::env::var_os("RELIEF_BLESS").is_some() {
        return Ok(()); // blessing passes every case, a new one too
    }
    let folder = std::env::temp_dir().join(format!("relief-golden-new-{}", std::process::id()));
    std::fs::create_dir_all(&folder).map_err(|e| e.to_string())?;
    let args = "# a new case\nrender --fbm-size 32 --seed 3 --size 24x16\n";
    std::fs::write(folder.join("new-case.args"), args).map_err(|e| e.to_string())?;
    let [case] = <[Case; 1]>::try_from(cases(&folder)).map_err(|c| format!("{c:?}"))?;
    let first = case.run();
    let written = case.reference().is_file();
    let second = case.run();
    let _ = std::fs::remove_dir_all(&folder);
    match first {
        Err(e) if e.contains("wrote") && written && second.is_ok() => Ok(()),
        other => {
            Err(format!("first run {other:?}, written {written}, second run {second:?}").into())
        }
    }
}
