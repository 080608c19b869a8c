//! A minimal reader of 64-bit little-endian ELF shared objects: the `DT_NEEDED` entries of
//! the dynamic section and the undefined dynamic symbols (what the object needs from other
//! libraries). Enough to check an FMU binary's dependencies without external tools.

use std::path::Path;

const SHT_DYNAMIC: u32 = 6;
const SHT_DYNSYM: u32 = 11;
const DT_NULL: u64 = 0;
const DT_NEEDED: u64 = 1;

/// What a shared object needs at load time.
#[derive(Debug, Clone, Default)]
pub struct Dependencies {
    /// `DT_NEEDED` library names, in file order.
    pub needed: Vec<String>,
    /// Names of undefined (imported) dynamic symbols.
    pub undefined_symbols: Vec<String>,
}

struct Section {
    kind: u32,
    offset: usize,
    size: usize,
    link: usize,
    entsize: usize,
}

fn u16_at(b: &[u8], o: usize) -> u16 {
    u16::from_le_bytes(b[o..o + 2].try_into().expect("2 bytes"))
}
fn u32_at(b: &[u8], o: usize) -> u32 {
    u32::from_le_bytes(b[o..o + 4].try_into().expect("4 bytes"))
}
fn u64_at(b: &[u8], o: usize) -> u64 {
    u64::from_le_bytes(b[o..o + 8].try_into().expect("8 bytes"))
}

fn c_str(b: &[u8], o: usize) -> Result<String, String> {
    let tail = b.get(o..).ok_or("string offset out of range")?;
    let end = tail
        .iter()
        .position(|&c| c == 0)
        .ok_or("unterminated string")?;
    Ok(String::from_utf8_lossy(&tail[..end]).into_owned())
}

/// Read the dependencies of the ELF64 LE file at `path`.
pub fn dependencies(path: &Path) -> Result<Dependencies, String> {
    let b = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let what = |m: &str| format!("{}: {m}", path.display());
    if b.len() < 64 || &b[..4] != b"\x7fELF" {
        return Err(what("not an ELF file"));
    }
    if b[4] != 2 || b[5] != 1 {
        return Err(what("not a 64-bit little-endian ELF file"));
    }
    let shoff = u64_at(&b, 0x28) as usize;
    let shentsize = u16_at(&b, 0x3A) as usize;
    let shnum = u16_at(&b, 0x3C) as usize;
    if shentsize < 64 || shoff + shnum * shentsize > b.len() {
        return Err(what("section header table out of range"));
    }
    let sections: Vec<Section> = (0..shnum)
        .map(|i| {
            let o = shoff + i * shentsize;
            Section {
                kind: u32_at(&b, o + 4),
                offset: u64_at(&b, o + 24) as usize,
                size: u64_at(&b, o + 32) as usize,
                link: u32_at(&b, o + 40) as usize,
                entsize: u64_at(&b, o + 56) as usize,
            }
        })
        .collect();
    let strtab = |s: &Section| -> Result<&Section, String> {
        sections
            .get(s.link)
            .ok_or_else(|| what("string table index out of range"))
    };
    let mut deps = Dependencies::default();
    let dynamic = sections
        .iter()
        .find(|s| s.kind == SHT_DYNAMIC)
        .ok_or_else(|| what("no dynamic section (not a shared object?)"))?;
    let dynstr = strtab(dynamic)?;
    for k in 0..dynamic.size / 16 {
        let o = dynamic.offset + 16 * k;
        let tag = u64_at(&b, o);
        if tag == DT_NULL {
            break;
        }
        if tag == DT_NEEDED {
            let name =
                c_str(&b, dynstr.offset + u64_at(&b, o + 8) as usize).map_err(|e| what(&e))?;
            deps.needed.push(name);
        }
    }
    if let Some(dynsym) = sections.iter().find(|s| s.kind == SHT_DYNSYM) {
        let symstr = strtab(dynsym)?;
        let entsize = if dynsym.entsize == 0 {
            24
        } else {
            dynsym.entsize
        };
        for k in 1..dynsym.size / entsize {
            let o = dynsym.offset + entsize * k;
            let shndx = u16_at(&b, o + 6);
            if shndx == 0 {
                let name =
                    c_str(&b, symstr.offset + u32_at(&b, o) as usize).map_err(|e| what(&e))?;
                if !name.is_empty() {
                    deps.undefined_symbols.push(name);
                }
            }
        }
    }
    Ok(deps)
}
