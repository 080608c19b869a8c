//! Reading input files with a size cap, so that a wrong path (`/dev/zero`, a video, a
//! multi-gigabyte log) is refused instead of being read until memory runs out; and only
//! regular files, so that a FIFO or a device is refused at once instead of blocking.

use std::io::{self, Read};
use std::path::Path;

/// Cap on a scenario file, bytes (16 MiB).
pub const MAX_SCENARIO_BYTES: u64 = 16 << 20;
/// Cap on a data file (modes file, track record), bytes (512 MiB).
pub const MAX_DATA_FILE_BYTES: u64 = 512 << 20;

/// The file's text, at most `limit` bytes of UTF-8, without a leading byte-order mark.
/// Errors say which limit was passed or at which byte the text stops being UTF-8.
pub fn read_text(path: &Path, limit: u64) -> io::Result<String> {
    // a FIFO would block the open until a writer came, a device would stream: only a
    // regular file (a link to one included) is read
    let kind = std::fs::metadata(path)?.file_type();
    if !kind.is_file() {
        return Err(io::Error::other(format!(
            "not a regular file ({}); give the path of a file",
            describe(&kind)
        )));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(io::Error::other(format!(
            "larger than the limit of {limit} bytes ({} MiB)",
            limit >> 20
        )));
    }
    // a UTF-8 byte-order mark (spreadsheet exports) is not part of the text
    let bom = if bytes.starts_with(b"\xEF\xBB\xBF") {
        3
    } else {
        0
    };
    bytes.drain(..bom);
    String::from_utf8(bytes).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "not valid UTF-8 at byte {}",
                bom + e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// What a path that is not a regular file is, for messages.
fn describe(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else {
        "not a file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caps_size_and_names_the_first_bad_byte() {
        let dir = std::env::temp_dir().join(format!("tbi-input-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.txt");
        std::fs::write(&p, b"hello").unwrap();
        assert_eq!(read_text(&p, 5).unwrap(), "hello");
        assert!(read_text(&p, 4)
            .unwrap_err()
            .to_string()
            .contains("limit of 4 bytes"));
        std::fs::write(&p, b"ab\xffcd").unwrap();
        assert!(read_text(&p, 100)
            .unwrap_err()
            .to_string()
            .contains("at byte 2"));
        // a byte-order mark is dropped; bytes are still counted from the file's start
        std::fs::write(&p, b"\xEF\xBB\xBFoffset_m,load_n\n").unwrap();
        assert_eq!(read_text(&p, 100).unwrap(), "offset_m,load_n\n");
        std::fs::write(&p, b"\xEF\xBB\xBFab\xff").unwrap();
        assert!(read_text(&p, 100)
            .unwrap_err()
            .to_string()
            .contains("at byte 5"));
        #[cfg(unix)]
        {
            let e = read_text(Path::new("/dev/zero"), 1 << 20)
                .unwrap_err()
                .to_string();
            assert!(e.contains("not a regular file (a device)"), "{e}");
            // a FIFO is refused at once (opening it would wait for a writer)
            let fifo = dir.join("pipe");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status();
            if made.is_ok_and(|s| s.success()) {
                let e = read_text(&fifo, 100).unwrap_err().to_string();
                assert!(e.contains("a FIFO"), "{e}");
            }
        }
        let e = read_text(&dir, 100).unwrap_err().to_string();
        assert!(e.contains("a folder"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
