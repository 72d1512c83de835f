//! Packs the FMUs and the system: `cargo run --release --bin relnav-fmu [-- OUT_DIR]`
//! writes relnav.fmu; `-- --all [OUT_DIR]` also relnav_plant.fmu, relnav_guidance.fmu and
//! relnav_system.ssp (`fmu/build.sh` builds the libraries first and runs this);
//! `-- --variables-markdown [MODEL]` prints a model's variable table (relnav, relnav_plant,
//! relnav_guidance) for the README and `docs/kit.md`.
//!
//! Each FMU goes to `OUT_DIR/<id>.fmu` (default `target/fmu/`) and, unpacked, to
//! `OUT_DIR/<id>/`: `modelDescription.xml` (FMI 2.0, generated from the model's variable
//! table) and `binaries/linux64/<id>.so` (the cdylib built next to this executable —
//! `librelnav_fmu.so` (fmu/relnav), `librelnav_plant.so`, `librelnav_guidance.so` — renamed).
//! `relnav3.fmu` (FMI 3.0, `OUT_DIR/relnav3/`; with `--all` also `relnav_plant3.fmu` and
//! `relnav_guidance3.fmu`) has the FMI 3.0 description and the same library under
//! `binaries/x86_64-linux/<id>.so` (each exports the `fmi3*` functions beside the `fmi2*`
//! ones). `relnav_system.ssp` holds the SSDs of `fmu/ssp/` (`SystemStructure.ssd`: paper 000's
//! example, the default; the other variants beside it, `docs/kit.md`) with the three FMUs
//! under `resources/` (stored: an FMU is a zip already).

use relnav_fmi::fmi2::description::{model_description_of, variables_markdown_of};
use relnav_fmi::fmi3::description::model_description_of as model_description3_of;
use relnav_fmi::model::ModelInfo;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The three FMUs: each model and the file name of its cdylib (crate in fmu/; relnav.fmu's
/// is `relnav_fmu`, since `librelnav.so` is the C-ABI library's name), relnav.fmu first.
fn fmus() -> [(&'static ModelInfo, &'static str); 3] {
    [
        (&relnav_nav_model::INFO, "librelnav_fmu.so"),
        (&relnav_models::plant::INFO, "librelnav_plant.so"),
        (&relnav_models::guidance::INFO, "librelnav_guidance.so"),
    ]
}

fn write(p: &Path, data: &[u8]) -> Result<(), String> {
    if let Some(d) = p.parent() {
        std::fs::create_dir_all(d).map_err(|e| format!("mkdir {}: {e}", d.display()))?;
    }
    std::fs::write(p, data).map_err(|e| format!("write {}: {e}", p.display()))
}

fn zerr(e: zip::result::ZipError) -> String {
    format!("zip: {e}")
}

/// The FMI version of an archive: its description, its binaries' platform directory and
/// the archive's name (FMI 3.0: `<id>3`, beside FMI 2.0's `<id>`).
#[derive(Clone, Copy)]
enum Version {
    Fmi2,
    Fmi3,
}

/// Pack one FMU from its cdylib `library` in `profile_dir`.
fn pack_fmu(
    info: &'static ModelInfo,
    library: &str,
    profile_dir: &Path,
    out_dir: &Path,
    version: Version,
) -> Result<PathBuf, String> {
    let id = info.model_identifier;
    let (xml, platform, stem) = match version {
        Version::Fmi2 => (model_description_of(info), "linux64", id.to_string()),
        Version::Fmi3 => (
            model_description3_of(info),
            "x86_64-linux",
            format!("{id}3"),
        ),
    };
    let so = profile_dir.join(library);
    if !so.exists() {
        return Err(format!(
            "{} not found: build the libraries first (fmu/build.sh)",
            so.display()
        ));
    }
    let binary = std::fs::read(&so).map_err(|e| format!("read {}: {e}", so.display()))?;
    let bin_path = format!("binaries/{platform}/{id}.so");

    // unpacked tree (for masters that load a directory, e.g. the C++ harness)
    let tree = out_dir.join(&stem);
    write(&tree.join("modelDescription.xml"), xml.as_bytes())?;
    write(&tree.join(&bin_path), &binary)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let p = tree.join(&bin_path);
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755))
            .map_err(|e| format!("chmod {}: {e}", p.display()))?;
    }

    // the archive
    let fmu = out_dir.join(format!("{stem}.fmu"));
    let file = std::fs::File::create(&fmu).map_err(|e| format!("create {}: {e}", fmu.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    zip.start_file("modelDescription.xml", opts).map_err(zerr)?;
    zip.write_all(xml.as_bytes()).map_err(|e| e.to_string())?;
    zip.start_file(bin_path.as_str(), opts.unix_permissions(0o755))
        .map_err(zerr)?;
    zip.write_all(&binary).map_err(|e| e.to_string())?;
    zip.finish().map_err(zerr)?;
    Ok(fmu)
}

/// Pack `relnav_system.ssp`: the SSDs of `fmu/ssp/` (`SystemStructure.ssd`, the default
/// variant, and the other variants beside it) and the FMUs they reference.
fn pack_ssp(fmus: &[PathBuf], out_dir: &Path) -> Result<PathBuf, String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../ssp");
    let mut ssds: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("read {}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ssd"))
        .collect();
    ssds.sort();
    if !ssds.iter().any(|p| p.ends_with("SystemStructure.ssd")) {
        return Err(format!("{} has no SystemStructure.ssd", dir.display()));
    }
    let ssp = out_dir.join("relnav_system.ssp");
    let file = std::fs::File::create(&ssp).map_err(|e| format!("create {}: {e}", ssp.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let deflated = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let stored = deflated.compression_method(zip::CompressionMethod::Stored);
    let mut texts = Vec::new();
    for p in &ssds {
        let text = std::fs::read_to_string(p).map_err(|e| format!("read {}: {e}", p.display()))?;
        let name = p
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| format!("bad SSD path {}", p.display()))?;
        zip.start_file(name, deflated).map_err(zerr)?;
        zip.write_all(text.as_bytes()).map_err(|e| e.to_string())?;
        texts.push(text);
    }
    for f in fmus {
        let name = f
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| format!("bad FMU path {}", f.display()))?;
        let source = format!("resources/{name}");
        if !texts
            .iter()
            .all(|t| t.contains(&format!("source=\"{source}\"")))
        {
            return Err(format!(
                "an SSD in {} does not reference {source}",
                dir.display()
            ));
        }
        let data = std::fs::read(f).map_err(|e| format!("read {}: {e}", f.display()))?;
        zip.start_file(source.as_str(), stored).map_err(zerr)?;
        zip.write_all(&data).map_err(|e| e.to_string())?;
    }
    zip.finish().map_err(zerr)?;
    Ok(ssp)
}

fn run(all: bool, out: Option<PathBuf>) -> Result<Vec<PathBuf>, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate myself: {e}"))?;
    let profile_dir = exe
        .parent()
        .ok_or("executable has no parent directory")?
        .to_path_buf();
    let target_dir = profile_dir.parent().ok_or("no target directory")?;
    let out_dir = out.unwrap_or_else(|| target_dir.join("fmu"));
    let all_fmus = fmus();
    let chosen = if all { &all_fmus[..] } else { &all_fmus[..1] };
    let pack = |version| {
        chosen
            .iter()
            .map(|(info, library)| pack_fmu(info, library, &profile_dir, &out_dir, version))
            .collect::<Result<Vec<_>, _>>()
    };
    let mut written = pack(Version::Fmi2)?;
    if all {
        let ssp = pack_ssp(&written, &out_dir)?;
        written.push(ssp);
    }
    // FMI 3.0: relnav3.fmu (and the kit's) from the same libraries (each exports both sets
    // of functions)
    written.extend(pack(Version::Fmi3)?);
    Ok(written)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--variables-markdown") {
        let id = args.get(1).map_or("relnav", String::as_str);
        return match fmus().into_iter().find(|m| m.0.model_identifier == id) {
            Some((info, _)) => {
                print!("{}", variables_markdown_of(info));
                ExitCode::SUCCESS
            }
            None => {
                eprintln!("relnav-fmu: unknown model {id} (relnav, relnav_plant, relnav_guidance)");
                ExitCode::FAILURE
            }
        };
    }
    let all = args.first().map(String::as_str) == Some("--all");
    let out = args.get(usize::from(all)).map(PathBuf::from);
    match run(all, out) {
        Ok(paths) => {
            for p in paths {
                let size = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
                println!("wrote {} ({} bytes)", p.display(), size);
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("relnav-fmu: {e}");
            ExitCode::FAILURE
        }
    }
}
