//! Writing FMU archives.
//!
//! [`write_fmu`] produces the standard FMI 2.0 layout with forward-slash names, the
//! description and documentation deflated, the library and resources stored (see
//! `write_zip`), and [`write_fmu3`] the FMI 3.0 one, whose binaries folder is named by
//! architecture and operating system:
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/<modelIdentifier>.so        (FMI 3.0: binaries/x86_64-linux/)
//! resources/<relative path>...
//! documentation/index.html            (optional)
//! ```
//!
//! Before writing, the description is parsed and its `<CoSimulation modelIdentifier>`
//! compared with `model_identifier`, and every resource path is checked to be relative,
//! `..`-free and unique, so the archive is one that the importer (`crate::fmi`) and other
//! tools accept. The zip is written next to `out` under a temporary name and renamed into
//! place, so `out` is either the complete new FMU or untouched. Entry timestamps are fixed
//! (1980-01-01), so the same inputs give byte-identical archives.

use model_description::ModelDescription;
use std::collections::HashSet;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

/// Writing an FMU failed; the message names the output file and the cause.
#[derive(Debug, thiserror::Error)]
#[error("{out}: {message}")]
pub struct PackageError {
    pub out: PathBuf,
    pub message: String,
}

fn check_resource_path(path: &str) -> Result<(), String> {
    if path.is_empty() {
        return Err("a resource has an empty path".into());
    }
    if path.contains('\\') || path.contains(':') || path.contains('\0') {
        return Err(format!(
            "resource path \"{path}\" contains a backslash, ':' or NUL (use relative paths with '/')"
        ));
    }
    if path.starts_with('/') || path.ends_with('/') {
        return Err(format!(
            "resource path \"{path}\" must be a relative file path (no leading or trailing '/')"
        ));
    }
    if path
        .split('/')
        .any(|part| part.is_empty() || part == "." || part == "..")
    {
        return Err(format!(
            "resource path \"{path}\" may only contain plain names (no '.', '..' or empty components)"
        ));
    }
    Ok(())
}

/// Write an FMI 2.0 Co-Simulation FMU to `out` (see the module documentation).
///
/// - `model_description_xml`: the complete `modelDescription.xml`; its CoSimulation
///   `modelIdentifier` must equal `model_identifier`.
/// - `shared_object`: the compiled library, stored as
///   `binaries/linux64/<model_identifier>.so`.
/// - `resources`: `(path relative to resources/, bytes)` pairs.
/// - `documentation_html`: stored as `documentation/index.html` when given.
pub fn write_fmu(
    out: &Path,
    model_description_xml: &str,
    model_identifier: &str,
    shared_object: &Path,
    resources: &[(String, Vec<u8>)],
    documentation_html: Option<&str>,
) -> Result<(), PackageError> {
    let fail = |message: String| PackageError {
        out: out.to_path_buf(),
        message,
    };
    let md = ModelDescription::parse(model_description_xml, "the model description")
        .map_err(|e| fail(e.to_string()))?;
    let fmu = Archive {
        xml: model_description_xml,
        platform: fmi_import::PLATFORM,
        model_identifier,
        shared_object,
        resources,
        documentation_html,
    };
    fmu.write(out, &md)
}

/// The folder of an FMI 3.0 FMU's binaries for this platform (`<arch>-<os>`).
pub const FMI3_PLATFORM: &str = "x86_64-linux";

/// Write the FMI 3.0 Co-Simulation FMU of the FMI 2.0 description `md` (same variables,
/// [`ModelDescription::to_fmi3_xml_string`]) to `out`, with the library under
/// `binaries/x86_64-linux/`; otherwise as [`write_fmu`].
pub fn write_fmu3(
    out: &Path,
    md: &ModelDescription,
    model_identifier: &str,
    shared_object: &Path,
    resources: &[(String, Vec<u8>)],
    documentation_html: Option<&str>,
) -> Result<(), PackageError> {
    let xml = md.to_fmi3_xml_string().map_err(|message| PackageError {
        out: out.to_path_buf(),
        message,
    })?;
    let fmu = Archive {
        xml: &xml,
        platform: FMI3_PLATFORM,
        model_identifier,
        shared_object,
        resources,
        documentation_html,
    };
    fmu.write(out, md)
}

/// What an FMU archive holds.
struct Archive<'a> {
    xml: &'a str,
    /// The folder of the binaries (`linux64`, `x86_64-linux`).
    platform: &'a str,
    model_identifier: &'a str,
    shared_object: &'a Path,
    resources: &'a [(String, Vec<u8>)],
    documentation_html: Option<&'a str>,
}

impl Archive<'_> {
    /// Check the archive against `md` (its FMI 2.0 description) and write it to `out`.
    fn write(&self, out: &Path, md: &ModelDescription) -> Result<(), PackageError> {
        let fail = |message: String| PackageError {
            out: out.to_path_buf(),
            message,
        };
        let (model_identifier, resources, shared_object) =
            (self.model_identifier, self.resources, self.shared_object);
        match &md.co_simulation {
        Some(cs) if cs.model_identifier == model_identifier => {}
        Some(cs) => {
            return Err(fail(format!(
                "the model description's modelIdentifier is \"{}\" but the library is packaged as \"{model_identifier}\"",
                cs.model_identifier
            )))
        }
        None => return Err(fail("the model description has no <CoSimulation> element".into())),
    }
        if model_identifier.is_empty()
            || !model_identifier
                .chars()
                .all(|c| c == '_' || c.is_ascii_alphanumeric())
            || model_identifier.starts_with(|c: char| c.is_ascii_digit())
        {
            return Err(fail(format!(
                "modelIdentifier \"{model_identifier}\" is not a valid C identifier"
            )));
        }
        let mut seen = HashSet::new();
        for (path, _) in resources {
            check_resource_path(path).map_err(&fail)?;
            if !seen.insert(path.as_str()) {
                return Err(fail(format!("resource path \"{path}\" is given twice")));
            }
        }
        let library = fs::read(shared_object).map_err(|e| {
            fail(format!(
                "cannot read the shared library {}: {e}",
                shared_object.display()
            ))
        })?;

        let file_name = out
            .file_name()
            .ok_or_else(|| fail("the output path has no file name".into()))?;
        let mut temp_name = std::ffi::OsString::from(".");
        temp_name.push(file_name);
        temp_name.push(format!(".{}.fmu.tmp", std::process::id()));
        let temp = out.with_file_name(temp_name);
        let result = write_zip(&temp, self, &library).and_then(|()| fs::rename(&temp, out));
        if let Err(e) = result {
            let _ = fs::remove_file(&temp);
            return Err(fail(format!("cannot write the archive: {e}")));
        }
        Ok(())
    }
}

fn write_zip(path: &Path, archive: &Archive, library: &[u8]) -> io::Result<()> {
    let (model_description_xml, model_identifier, platform) =
        (archive.xml, archive.model_identifier, archive.platform);
    let (resources, documentation_html) = (archive.resources, archive.documentation_html);
    let file = fs::File::create(path)?;
    let mut zip = zip::ZipWriter::new(io::BufWriter::new(file));
    // The description and the documentation are deflated (text that shrinks to a few per
    // cent). The shared library and the resources are stored: they are the bulk of the
    // archive (the bridge FMU's library and track record), every run unpacks them, and
    // inflating them cost more of a run's setup than their size on disk is worth.
    let file_options = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .compression_level(Some(3))
        .unix_permissions(0o644);
    let stored_options = file_options
        .compression_method(CompressionMethod::Stored)
        .compression_level(None);
    let library_options = stored_options.unix_permissions(0o755);
    let dir_options = SimpleFileOptions::default().unix_permissions(0o755);

    zip.start_file("modelDescription.xml", file_options)?;
    zip.write_all(model_description_xml.as_bytes())?;

    zip.add_directory("binaries/", dir_options)?;
    zip.add_directory(format!("binaries/{platform}/"), dir_options)?;
    zip.start_file(
        format!("binaries/{platform}/{model_identifier}.so"),
        library_options,
    )?;
    zip.write_all(library)?;

    if !resources.is_empty() {
        zip.add_directory("resources/", dir_options)?;
        let mut dirs = HashSet::new();
        let mut sorted: Vec<&(String, Vec<u8>)> = resources.iter().collect();
        sorted.sort_by(|a, b| a.0.cmp(&b.0));
        for (relative, bytes) in sorted {
            let parts: Vec<&str> = relative.split('/').collect();
            for depth in 1..parts.len() {
                let dir = format!("resources/{}/", parts[..depth].join("/"));
                if dirs.insert(dir.clone()) {
                    zip.add_directory(dir, dir_options)?;
                }
            }
            zip.start_file(format!("resources/{relative}"), stored_options)?;
            zip.write_all(bytes)?;
        }
    }

    if let Some(html) = documentation_html {
        zip.add_directory("documentation/", dir_options)?;
        zip.start_file("documentation/index.html", file_options)?;
        zip.write_all(html.as_bytes())?;
    }
    let mut writer = zip.finish()?;
    writer.flush()?;
    writer.get_ref().sync_all()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmi_import::archive::UnpackedDir;
    use std::io::Read;

    const XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="{g}">
  <CoSimulation modelIdentifier="m_model"/>
  <ModelVariables/>
  <ModelStructure/>
</fmiModelDescription>
"#;

    fn fixture() -> (UnpackedDir, PathBuf) {
        let dir = UnpackedDir::create("tbi-package-test").unwrap();
        let so = dir.path().join("libm_model.so");
        fs::write(&so, b"\x7fELF not really").unwrap();
        (dir, so)
    }

    #[test]
    fn writes_the_standard_layout() {
        let (dir, so) = fixture();
        let out = dir.path().join("M.fmu");
        let resources = vec![
            ("table.csv".to_owned(), b"t,x\n0,1\n".to_vec()),
            ("modes/bridge.json".to_owned(), b"{}".to_vec()),
        ];
        write_fmu(&out, XML, "m_model", &so, &resources, Some("<html/>")).unwrap();
        let mut zip = zip::ZipArchive::new(fs::File::open(&out).unwrap()).unwrap();
        let mut names: Vec<String> = zip.file_names().map(|n| n.unwrap().into_owned()).collect();
        names.sort();
        assert_eq!(
            names,
            [
                "binaries/",
                "binaries/linux64/",
                "binaries/linux64/m_model.so",
                "documentation/",
                "documentation/index.html",
                "modelDescription.xml",
                "resources/",
                "resources/modes/",
                "resources/modes/bridge.json",
                "resources/table.csv",
            ]
        );
        let mut text = String::new();
        zip.by_name("modelDescription.xml")
            .unwrap()
            .read_to_string(&mut text)
            .unwrap();
        assert_eq!(text, XML);
        let entry = zip.by_name("binaries/linux64/m_model.so").unwrap();
        assert_eq!(entry.compression(), CompressionMethod::Stored);
        assert_eq!(entry.unix_mode().map(|m| m & 0o777), Some(0o755));
        drop(entry);
        assert_eq!(
            zip.by_name("modelDescription.xml").unwrap().compression(),
            CompressionMethod::Deflated
        );
        let mut table = Vec::new();
        let mut entry = zip.by_name("resources/table.csv").unwrap();
        assert_eq!(entry.compression(), CompressionMethod::Stored);
        entry.read_to_end(&mut table).unwrap();
        drop(entry);
        assert_eq!(table, b"t,x\n0,1\n");
        // no temporary file left behind
        let leftovers: Vec<_> = fs::read_dir(dir.path())
            .unwrap()
            .filter_map(Result::ok)
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty());
    }

    #[test]
    fn output_is_reproducible() {
        let (dir, so) = fixture();
        let a = dir.path().join("a.fmu");
        let b = dir.path().join("b.fmu");
        let res = vec![("x".to_owned(), vec![1, 2, 3])];
        write_fmu(&a, XML, "m_model", &so, &res, None).unwrap();
        write_fmu(&b, XML, "m_model", &so, &res, None).unwrap();
        assert_eq!(fs::read(a).unwrap(), fs::read(b).unwrap());
    }

    #[test]
    fn refuses_inconsistent_input() {
        let (dir, so) = fixture();
        let out = dir.path().join("bad.fmu");
        let e = write_fmu(&out, XML, "other", &so, &[], None)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("modelIdentifier is \"m_model\" but the library is packaged as \"other\""),
            "{e}"
        );
        for bad in ["../x", "/abs", "a\\b", "a//b", "a/./b", "dir/", ""] {
            let res = vec![(bad.to_owned(), vec![])];
            let e = write_fmu(&out, XML, "m_model", &so, &res, None).unwrap_err();
            assert!(
                e.to_string().starts_with(&format!("{}: ", out.display())),
                "{e}"
            );
        }
        let twice = vec![("a".to_owned(), vec![]), ("a".to_owned(), vec![])];
        let e = write_fmu(&out, XML, "m_model", &so, &twice, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("resource path \"a\" is given twice"), "{e}");
        let e = write_fmu(&out, "<oops", "m_model", &so, &[], None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("the model description: malformed XML"), "{e}");
        let e = write_fmu(&out, XML, "m_model", &dir.path().join("none.so"), &[], None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot read the shared library"), "{e}");
        assert!(!out.exists());
    }
}
