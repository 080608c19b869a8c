//! Saved FMU states: the in-memory snapshot behind `fmi2FMUstate` and its byte format.
//!
//! A snapshot is the framework's part of the dynamic state ([`Frame`]: machine state,
//! time, start/stop time, the "terminate requested" flag) plus a `Clone` of the model.
//! `fmi2GetFMUstate` boxes one and hands out the raw pointer; the importer owns it until
//! `fmi2FreeFMUstate`. Snapshots start with a magic number and a per-model-type tag so a
//! pointer that is not a snapshot of this FMU is (best effort) refused rather than used.
//!
//! # Serialized format (version 1)
//!
//! All integers little-endian, `f64` as IEEE-754 bits:
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `b"FMI2RsSt"` |
//! | 8 | 4 | format version (`1`) |
//! | 12 | 8 | FNV-1a 64 of the model identifier |
//! | 20 | 8 | FNV-1a 64 of the GUID |
//! | 28 | 2 | machine state bit ([`State::bit`]) |
//! | 30 | 8 | time |
//! | 38 | 8 | start time |
//! | 46 | 1 | stop time defined (0/1) |
//! | 47 | 8 | stop time (0 when undefined) |
//! | 55 | 1 | terminate requested (0/1) |
//! | 56 | 8 | model payload length `n` |
//! | 64 | n | [`crate::FmuModel::serialize_state`] |
//! | 64+n | 8 | FNV-1a 64 of bytes `0..64+n` |
//!
//! Bytes from another FMU (model identifier), another build or resource set (GUID), a
//! newer format, or damaged in transit (checksum, lengths, invalid fields) are refused
//! with a message saying which.

use crate::guid::fnv1a64;
use crate::state::State;

/// The framework's part of an instance's dynamic state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub state: State,
    /// Internal time: the end of the last successful communication step.
    pub time: f64,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    /// Set when `fmi2DoStep` returned `fmi2Discard` (reported by
    /// `fmi2GetBooleanStatus(fmi2Terminated)`).
    pub terminate_requested: bool,
}

impl Frame {
    /// Right after `fmi2Instantiate` / `fmi2Reset`.
    pub const fn instantiated() -> Frame {
        Frame {
            state: State::Instantiated,
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            terminate_requested: false,
        }
    }
}

const SNAPSHOT_MAGIC: u64 = 0x5453_5f32_494d_4673; // "sFMI2_ST"

/// The object behind an `fmi2FMUstate` pointer.
#[repr(C)]
pub struct Snapshot<M> {
    magic: u64,
    type_tag: u64,
    pub frame: Frame,
    pub model: M,
}

impl<M> std::fmt::Debug for Snapshot<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Snapshot")
            .field("frame", &self.frame)
            .finish_non_exhaustive()
    }
}

impl<M> Snapshot<M> {
    pub fn new(type_tag: u64, frame: Frame, model: M) -> Snapshot<M> {
        Snapshot {
            magic: SNAPSHOT_MAGIC,
            type_tag,
            frame,
            model,
        }
    }

    /// Resolve an `fmi2FMUstate` handed back by the importer.
    ///
    /// # Safety
    /// `ptr` must be NULL or point to readable memory of at least 16 bytes; it is turned
    /// into a reference only if both header words match, and then must be a live
    /// `Snapshot<M>` created by this crate and not freed. The header check catches
    /// pointers of another FMU or a snapshot freed through `fmi2FreeFMUstate` while its
    /// memory is still mapped; it cannot make arbitrary pointers safe.
    pub unsafe fn from_handle<'a>(
        ptr: *mut std::ffi::c_void,
        type_tag: u64,
    ) -> Result<&'a mut Snapshot<M>, String> {
        if ptr.is_null() {
            return Err("the FMU state pointer is NULL".to_owned());
        }
        let header = ptr as *const u64;
        // SAFETY: caller guarantees 16 readable bytes; unaligned reads avoid assuming
        // alignment of a foreign pointer.
        let (magic, tag) = unsafe { (header.read_unaligned(), header.add(1).read_unaligned()) };
        if magic != SNAPSHOT_MAGIC {
            return Err("the pointer is not an FMU state created by fmi2GetFMUstate or fmi2DeSerializeFMUstate of this FMU (or it was freed)".to_owned());
        }
        if tag != type_tag {
            return Err("the FMU state belongs to a different FMU".to_owned());
        }
        // SAFETY: header matches, so per the contract this is a live Snapshot<M>.
        Ok(unsafe { &mut *(ptr as *mut Snapshot<M>) })
    }

    /// Mark as freed (so a dangling handle is recognised while the memory is mapped).
    pub fn invalidate(&mut self) {
        self.magic = 0;
    }
}

const MAGIC: &[u8; 8] = b"FMI2RsSt";
const FORMAT_VERSION: u32 = 1;
const HEADER_LEN: usize = 64;
const CHECKSUM_LEN: usize = 8;

/// Identity of the FMU a serialized state belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Identity {
    pub model_identifier_hash: u64,
    pub guid_hash: u64,
}

impl Identity {
    pub fn new(model_identifier: &str, guid: &str) -> Identity {
        Identity {
            model_identifier_hash: fnv1a64(model_identifier.as_bytes()),
            guid_hash: fnv1a64(guid.as_bytes()),
        }
    }
}

/// Serialize a frame and a model payload.
pub fn encode(identity: Identity, frame: &Frame, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len() + CHECKSUM_LEN);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&identity.model_identifier_hash.to_le_bytes());
    out.extend_from_slice(&identity.guid_hash.to_le_bytes());
    out.extend_from_slice(&frame.state.bit().to_le_bytes());
    out.extend_from_slice(&frame.time.to_le_bytes());
    out.extend_from_slice(&frame.start_time.to_le_bytes());
    out.push(u8::from(frame.stop_time.is_some()));
    out.extend_from_slice(&frame.stop_time.unwrap_or(0.0).to_le_bytes());
    out.push(u8::from(frame.terminate_requested));
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    debug_assert_eq!(out.len(), HEADER_LEN);
    out.extend_from_slice(payload);
    let checksum = fnv1a64(&out);
    out.extend_from_slice(&checksum.to_le_bytes());
    out
}

/// Parse bytes written by [`encode`] for the FMU `expected`; returns the frame and the
/// model payload.
pub fn decode(bytes: &[u8], expected: Identity) -> Result<(Frame, &[u8]), String> {
    if bytes.len() < HEADER_LEN + CHECKSUM_LEN {
        return Err(format!(
            "{} bytes are too short for a serialized FMU state (at least {})",
            bytes.len(),
            HEADER_LEN + CHECKSUM_LEN
        ));
    }
    if &bytes[0..8] != MAGIC {
        return Err(
            "the bytes are not a serialized FMU state of this plumbing (bad magic)".to_owned(),
        );
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if version != FORMAT_VERSION {
        return Err(format!(
            "serialized FMU state format version {version} is not supported (expected {FORMAT_VERSION})"
        ));
    }
    let (body, checksum) = bytes.split_at(bytes.len() - CHECKSUM_LEN);
    if fnv1a64(body) != u64_at(checksum, 0) {
        return Err("the serialized FMU state is corrupted (checksum mismatch)".to_owned());
    }
    if u64_at(bytes, 12) != expected.model_identifier_hash {
        return Err(
            "the serialized FMU state belongs to a different FMU (model identifier differs)"
                .to_owned(),
        );
    }
    if u64_at(bytes, 20) != expected.guid_hash {
        return Err("the serialized FMU state was written by a different build or resource set of this FMU (GUID differs)".to_owned());
    }
    let state_bit = u16::from_le_bytes(bytes[28..30].try_into().expect("2 bytes"));
    let state = State::from_bit(state_bit)
        .filter(|s| !matches!(s, State::StartAndEnd | State::StepInProgress | State::Fatal))
        .ok_or_else(|| format!("invalid machine state {state_bit:#x} in serialized FMU state"))?;
    let time = f64_at(bytes, 30);
    let start_time = f64_at(bytes, 38);
    let stop_time = match bytes[46] {
        0 => None,
        1 => Some(f64_at(bytes, 47)),
        b => {
            return Err(format!(
                "invalid stop-time flag {b} in serialized FMU state"
            ))
        }
    };
    let terminate_requested = match bytes[55] {
        0 => false,
        1 => true,
        b => {
            return Err(format!(
                "invalid terminate flag {b} in serialized FMU state"
            ))
        }
    };
    if !(time.is_finite() && start_time.is_finite() && stop_time.is_none_or(f64::is_finite)) {
        return Err("non-finite time in serialized FMU state".to_owned());
    }
    let payload_len = u64_at(bytes, 56);
    if payload_len != (body.len() - HEADER_LEN) as u64 {
        return Err(format!(
            "serialized FMU state declares {payload_len} model bytes but carries {}",
            body.len() - HEADER_LEN
        ));
    }
    let frame = Frame {
        state,
        time,
        start_time,
        stop_time,
        terminate_requested,
    };
    Ok((frame, &body[HEADER_LEN..]))
}

fn u64_at(bytes: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"))
}

fn f64_at(bytes: &[u8], at: usize) -> f64 {
    f64::from_bits(u64_at(bytes, at))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> Frame {
        Frame {
            state: State::StepComplete,
            time: 0.125,
            start_time: -1.0,
            stop_time: Some(10.0),
            terminate_requested: true,
        }
    }

    fn id() -> Identity {
        Identity::new("bridge", "0000-guid")
    }

    #[test]
    fn round_trip_preserves_frame_and_payload() {
        let payload = [1u8, 2, 3, 250];
        let bytes = encode(id(), &frame(), &payload);
        assert_eq!(bytes.len(), HEADER_LEN + payload.len() + CHECKSUM_LEN);
        let (f, p) = decode(&bytes, id()).unwrap();
        assert_eq!(f, frame());
        assert_eq!(p, payload);

        let f2 = Frame {
            stop_time: None,
            terminate_requested: false,
            ..frame()
        };
        let bytes = encode(id(), &f2, &[]);
        let (f, p) = decode(&bytes, id()).unwrap();
        assert_eq!(f, f2);
        assert!(p.is_empty());
    }

    #[test]
    fn foreign_bytes_are_refused_with_a_reason() {
        let bytes = encode(id(), &frame(), b"payload");
        let err = |b: &[u8], who: Identity| decode(b, who).unwrap_err();

        assert!(err(&bytes, Identity::new("train", "0000-guid")).contains("different FMU"));
        assert!(err(&bytes, Identity::new("bridge", "other")).contains("GUID differs"));
        assert!(err(&bytes[..bytes.len() - 1], id()).contains("checksum"));
        assert!(err(&bytes[..10], id()).contains("too short"));
        assert!(err(&[0u8; 100], id()).contains("bad magic"));

        let mut flipped = bytes.clone();
        flipped[HEADER_LEN + 2] ^= 0x01;
        assert!(err(&flipped, id()).contains("checksum"));

        let mut newer = bytes.clone();
        newer[8] = 2;
        assert!(err(&newer, id()).contains("version 2"));
    }

    #[test]
    fn invalid_fields_are_refused_even_with_a_valid_checksum() {
        let reseal = |mut b: Vec<u8>| {
            let n = b.len() - CHECKSUM_LEN;
            let c = fnv1a64(&b[..n]);
            b[n..].copy_from_slice(&c.to_le_bytes());
            b
        };
        let bytes = encode(id(), &frame(), b"xyz");

        let mut bad_state = bytes.clone();
        bad_state[28..30].copy_from_slice(&State::Fatal.bit().to_le_bytes());
        assert!(decode(&reseal(bad_state), id())
            .unwrap_err()
            .contains("machine state"));

        let mut bad_len = bytes.clone();
        bad_len[56] = 9;
        assert!(decode(&reseal(bad_len), id())
            .unwrap_err()
            .contains("declares 9"));

        let mut nan_time = bytes.clone();
        nan_time[30..38].copy_from_slice(&f64::NAN.to_le_bytes());
        assert!(decode(&reseal(nan_time), id())
            .unwrap_err()
            .contains("non-finite"));

        let mut bad_flag = bytes;
        bad_flag[46] = 7;
        assert!(decode(&reseal(bad_flag), id())
            .unwrap_err()
            .contains("stop-time flag"));
    }

    #[test]
    fn snapshot_handles_are_checked() {
        let mut s = Box::new(Snapshot::new(42, frame(), 7u32));
        let p = &mut *s as *mut Snapshot<u32> as *mut std::ffi::c_void;
        unsafe {
            assert_eq!(Snapshot::<u32>::from_handle(p, 42).unwrap().model, 7);
            assert!(Snapshot::<u32>::from_handle(p, 43)
                .unwrap_err()
                .contains("different FMU"));
            assert!(Snapshot::<u32>::from_handle(std::ptr::null_mut(), 42)
                .unwrap_err()
                .contains("NULL"));
        }
        s.invalidate();
        unsafe {
            assert!(Snapshot::<u32>::from_handle(p, 42)
                .unwrap_err()
                .contains("not an FMU state"));
        }
        let mut not_a_snapshot = [0u64; 4];
        let q = not_a_snapshot.as_mut_ptr() as *mut std::ffi::c_void;
        unsafe {
            assert!(Snapshot::<u32>::from_handle(q, 42).is_err());
        }
    }
}
