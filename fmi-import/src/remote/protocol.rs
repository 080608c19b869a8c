//! The messages between a master and an FMU worker: length-prefixed frames (`u32` little
//! endian, then the bytes) on the worker's standard input and a pipe of its own, each
//! request an operation byte and its arguments, each reply a status byte (`0` done, `1`
//! failed with a message) and the values asked for. Numbers are little endian; `f64`s
//! travel as their bits, so values cross unchanged.

use std::io::{self, Read, Write};

/// The operations, one byte each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Op {
    /// path, instance name, echo the FMU's log (u8) → (reply)
    Load = 1,
    /// tolerance (flag + f64), start, stop (flag + f64)
    SetupExperiment = 2,
    EnterInitialization = 3,
    ExitInitialization = 4,
    /// vrs, f64s; no reply (a failure is reported by the next call that has one)
    SetReal = 5,
    /// vrs → f64s
    GetReal = 6,
    /// vrs, i32s; no reply
    SetInteger = 7,
    /// vrs → i32s
    GetInteger = 8,
    /// vrs, i32s (0/1); no reply
    SetBoolean = 9,
    /// vrs → i32s (0/1)
    GetBoolean = 10,
    /// vrs, strings
    SetString = 11,
    /// t, h, noSetFMUStatePriorToCurrentPoint (u8) → discarded (u8)
    DoStep = 12,
    /// no reply (as the setters)
    SaveState = 13,
    /// no reply (as the setters)
    RestoreState = 14,
    /// t, h, noSetFMUStatePriorToCurrentPoint (u8), vrs → discarded (u8), then the Reals
    /// of `vrs` after the step: `0` and the values, or `1` and the message of their
    /// `fmi2GetReal`'s failure
    DoStepGet = 15,
    /// → terminated (u8)
    Terminated = 16,
    /// → last successful time (f64)
    LastSuccessfulTime = 17,
    Terminate = 18,
}

impl Op {
    pub fn from_u8(b: u8) -> Option<Op> {
        use Op::*;
        Some(match b {
            1 => Load,
            2 => SetupExperiment,
            3 => EnterInitialization,
            4 => ExitInitialization,
            5 => SetReal,
            6 => GetReal,
            7 => SetInteger,
            8 => GetInteger,
            9 => SetBoolean,
            10 => GetBoolean,
            11 => SetString,
            12 => DoStep,
            13 => SaveState,
            14 => RestoreState,
            15 => DoStepGet,
            16 => Terminated,
            17 => LastSuccessfulTime,
            18 => Terminate,
            _ => return None,
        })
    }

    /// Whether the worker answers this operation (the value setters are pipelined).
    pub fn replies(self) -> bool {
        !matches!(
            self,
            Op::SetReal | Op::SetInteger | Op::SetBoolean | Op::SaveState | Op::RestoreState
        )
    }

    /// The FMI function, for messages.
    pub fn call(self) -> &'static str {
        use Op::*;
        match self {
            Load => "loading and fmi2Instantiate",
            SetupExperiment => "fmi2SetupExperiment",
            EnterInitialization => "fmi2EnterInitializationMode",
            ExitInitialization => "fmi2ExitInitializationMode",
            SetReal => "fmi2SetReal",
            GetReal => "fmi2GetReal",
            SetInteger => "fmi2SetInteger",
            GetInteger => "fmi2GetInteger",
            SetBoolean => "fmi2SetBoolean",
            GetBoolean => "fmi2GetBoolean",
            SetString => "fmi2SetString",
            DoStep | DoStepGet => "fmi2DoStep",
            SaveState => "fmi2GetFMUstate",
            RestoreState => "fmi2SetFMUstate",
            Terminated => "fmi2GetBooleanStatus(fmi2Terminated)",
            LastSuccessfulTime => "fmi2GetRealStatus(fmi2LastSuccessfulTime)",
            Terminate => "fmi2Terminate",
        }
    }
}

/// A message being written.
#[derive(Debug, Default)]
pub struct Out(pub Vec<u8>);

impl Out {
    pub fn op(op: Op) -> Out {
        Out(vec![op as u8])
    }
    pub fn u8(mut self, v: u8) -> Self {
        self.0.push(v);
        self
    }
    pub fn f64(mut self, v: f64) -> Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    pub fn opt_f64(self, v: Option<f64>) -> Self {
        match v {
            Some(v) => self.u8(1).f64(v),
            None => self.u8(0).f64(0.0),
        }
    }
    pub fn u32s(mut self, v: &[u32]) -> Self {
        self.0.extend_from_slice(&(v.len() as u32).to_le_bytes());
        for x in v {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        self
    }
    pub fn i32s(mut self, v: &[i32]) -> Self {
        self.0.extend_from_slice(&(v.len() as u32).to_le_bytes());
        for x in v {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        self
    }
    pub fn f64s(mut self, v: &[f64]) -> Self {
        self.0.extend_from_slice(&(v.len() as u32).to_le_bytes());
        for x in v {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        self
    }
    pub fn str(mut self, s: &str) -> Self {
        self.0.extend_from_slice(&(s.len() as u32).to_le_bytes());
        self.0.extend_from_slice(s.as_bytes());
        self
    }
}

/// A message being read; a short or malformed one is an error.
pub struct In<'a>(pub &'a [u8]);

fn short() -> String {
    "the worker's message is cut short".into()
}

impl In<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        if self.0.len() < n {
            return Err(short());
        }
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        Ok(head)
    }
    pub fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().expect("4 bytes"),
        ))
    }
    pub fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(
            self.take(8)?.try_into().expect("8 bytes"),
        ))
    }
    pub fn opt_f64(&mut self) -> Result<Option<f64>, String> {
        let set = self.u8()? != 0;
        let v = self.f64()?;
        Ok(set.then_some(v))
    }
    fn count(&mut self, size: usize) -> Result<usize, String> {
        let n = self.u32()? as usize;
        if n.saturating_mul(size) > self.0.len() {
            return Err(short());
        }
        Ok(n)
    }
    pub fn u32s(&mut self) -> Result<Vec<u32>, String> {
        let n = self.count(4)?;
        (0..n).map(|_| self.u32()).collect()
    }
    pub fn i32s(&mut self) -> Result<Vec<i32>, String> {
        let n = self.count(4)?;
        (0..n).map(|_| self.u32().map(|v| v as i32)).collect()
    }
    pub fn f64s(&mut self) -> Result<Vec<f64>, String> {
        let n = self.count(8)?;
        (0..n).map(|_| self.f64()).collect()
    }
    pub fn str(&mut self) -> Result<String, String> {
        let n = self.count(1)?;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| "a string is not UTF-8".into())
    }
}

/// Largest frame either side accepts (a bound, not a size any call comes near).
pub const MAX_FRAME: u32 = 1 << 30;

/// Writes one frame.
pub fn write_frame(w: &mut impl Write, bytes: &[u8]) -> io::Result<()> {
    w.write_all(&(bytes.len() as u32).to_le_bytes())?;
    w.write_all(bytes)
}

/// Reads one frame; `Ok(None)` at the end of the stream.
pub fn read_frame(r: &mut impl Read) -> io::Result<Option<Vec<u8>>> {
    let mut len = [0u8; 4];
    match r.read_exact(&mut len) {
        Ok(()) => {}
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => return Ok(None),
        Err(e) => return Err(e),
    }
    let n = u32::from_le_bytes(len);
    if n > MAX_FRAME {
        return Err(io::Error::other(format!("a frame of {n} bytes")));
    }
    let mut bytes = vec![0; n as usize];
    r.read_exact(&mut bytes)?;
    Ok(Some(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_cross_unchanged() {
        let f = [0.1, -0.0, f64::MIN_POSITIVE, 1e308, -3.5];
        let m = Out::op(Op::SetReal)
            .u32s(&[1, 7])
            .f64s(&f)
            .i32s(&[-4, 9])
            .opt_f64(None)
            .opt_f64(Some(2.5))
            .str("ws[1].F_z");
        let mut frame = Vec::new();
        write_frame(&mut frame, &m.0).unwrap();
        let bytes = read_frame(&mut frame.as_slice()).unwrap().unwrap();
        let mut i = In(&bytes);
        assert_eq!(Op::from_u8(i.u8().unwrap()), Some(Op::SetReal));
        assert_eq!(i.u32s().unwrap(), [1, 7]);
        let back = i.f64s().unwrap();
        assert!(back.iter().zip(f).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(i.i32s().unwrap(), [-4, 9]);
        assert_eq!(i.opt_f64().unwrap(), None);
        assert_eq!(i.opt_f64().unwrap(), Some(2.5));
        assert_eq!(i.str().unwrap(), "ws[1].F_z");
        assert!(i.u8().is_err(), "nothing is left");
        // a count larger than the message is refused, not allocated
        let mut bad = In(&[255, 255, 255, 127]);
        assert!(bad.f64s().is_err());
        assert_eq!(read_frame(&mut [].as_slice()).unwrap(), None);
    }
}
