//! Packs the FMU: `cargo run --release --bin relnav-fmu [-- OUT_DIR]`
//! (`-- --variables-markdown` prints the variable table for the README instead).
//!
//! Writes `OUT_DIR/relnav.fmu` (default `target/fmu/relnav.fmu`) and the same tree unpacked
//! in `OUT_DIR/relnav/`: `modelDescription.xml` (generated from the variable table) and
//! `binaries/linux64/relnav.so` (the cdylib built next to this executable, renamed).

use relnav::fmi::description::{model_description, MODEL_IDENTIFIER};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

fn run() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate myself: {e}"))?;
    let profile_dir = exe
        .parent()
        .ok_or("executable has no parent directory")?
        .to_path_buf();
    let so = profile_dir.join("librelnav.so");
    if !so.exists() {
        return Err(format!(
            "{} not found: build the library first (cargo build --release)",
            so.display()
        ));
    }
    let target_dir = profile_dir.parent().ok_or("no target directory")?;
    let out_dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| target_dir.join("fmu"));
    let binary = std::fs::read(&so).map_err(|e| format!("read {}: {e}", so.display()))?;
    let xml = model_description();
    let bin_path = format!("binaries/linux64/{MODEL_IDENTIFIER}.so");

    // unpacked tree (for masters that load a directory, e.g. the C++ harness)
    let tree = out_dir.join(MODEL_IDENTIFIER);
    let write = |p: &Path, data: &[u8]| -> Result<(), String> {
        if let Some(d) = p.parent() {
            std::fs::create_dir_all(d).map_err(|e| format!("mkdir {}: {e}", d.display()))?;
        }
        std::fs::write(p, data).map_err(|e| format!("write {}: {e}", p.display()))
    };
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
    let fmu = out_dir.join(format!("{MODEL_IDENTIFIER}.fmu"));
    let file = std::fs::File::create(&fmu).map_err(|e| format!("create {}: {e}", fmu.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let zerr = |e: zip::result::ZipError| format!("zip: {e}");
    zip.start_file("modelDescription.xml", opts).map_err(zerr)?;
    zip.write_all(xml.as_bytes()).map_err(|e| e.to_string())?;
    zip.start_file(bin_path.as_str(), opts.unix_permissions(0o755))
        .map_err(zerr)?;
    zip.write_all(&binary).map_err(|e| e.to_string())?;
    zip.finish().map_err(zerr)?;
    Ok(fmu)
}

fn main() -> ExitCode {
    if std::env::args().nth(1).as_deref() == Some("--variables-markdown") {
        print!("{}", relnav::fmi::description::variables_markdown());
        return ExitCode::SUCCESS;
    }
    match run() {
        Ok(p) => {
            let size = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
            println!("wrote {} ({} bytes)", p.display(), size);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("relnav-fmu: {e}");
            ExitCode::FAILURE
        }
    }
}
