//! Explicit, versioned bytes for saved state (the estimators' own state, the navigator's,
//! the FMU's): a little-endian [`Writer`] and a bounds-checked [`Reader`], the [`Persist`]
//! trait each filter implements beside its definition, and the [`seal`] / [`open`]
//! envelope (magic, format version, identity, payload length, CRC-32) around a payload.
//!
//! Every value is written field by field in little-endian byte order — never a memory copy
//! of a struct — so the bytes mean the same on every machine and in every build:
//! `u8`/`bool` one byte (`bool` 0 or 1), `u32`/`i32` four, `u64`/`i64`/`usize` eight
//! (`usize` as `u64`), `f64` the eight bytes of its IEEE-754 bit pattern (NaN payloads and
//! signed zeros kept, so a restore is bit-exact), matrices and vectors their entries
//! **column by column** (nalgebra's storage order). The layouts built from these pieces are
//! documented in `docs/state-format.md`.
//!
//! Lives below the estimators (which implement [`Persist`]); imports nothing from them.

use nalgebra::SMatrix;

/// Why a saved state was refused: a readable reason (truncated, corrupted, another format
/// version, another configuration, an out-of-range field).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateError(pub crate::message::Message);

impl core::fmt::Display for StateError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Magic of a navigator's (the C ABI estimator's) saved state.
pub const ESTIMATOR_MAGIC: &[u8; 8] = b"RELNAVES";
/// Magic of an FMU instance's saved state.
pub const FMU_MAGIC: &[u8; 8] = b"RELNAVFM";
/// The kinds of relnav state, for [`open`]'s message on a state of the wrong kind.
pub const KINDS: [(&[u8; 8], &str); 2] = [
    (ESTIMATOR_MAGIC, "a relnav estimator state"),
    (FMU_MAGIC, "a relnav FMU state"),
];

/// Shorthand for a [`StateError`].
pub fn refuse(message: impl Into<crate::message::Message>) -> StateError {
    StateError(message.into())
}

/// State that can be saved to and restored from explicit bytes. Implemented beside each
/// filter's definition: `save_state` writes every field that a later step reads (not the
/// configuration, which the caller checks separately, nor scratch buffers that every step
/// overwrites before reading), and `load_state` reads them back in the same order.
///
/// Implementations destructure `Self` exhaustively (no `..`), so a new field does not
/// compile until its author has decided whether it is state (saved) or scratch/configuration
/// (named with `_` and a comment); `tests/state.rs` then checks the round trip bit for bit.
pub trait Persist {
    /// Append the state to `w`.
    fn save_state(&self, w: &mut Writer<'_>);
    /// Read the state written by [`Persist::save_state`] into `self`, which was built from
    /// the same configuration (it supplies the sizes and what the configuration
    /// determines). On error `self` may be partly overwritten: callers restore into a copy
    /// and keep it only on success (restores are transactional).
    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError>;
}

/// Where a [`Writer`]'s bytes go.
enum Sink<'a> {
    /// Nowhere: the writer counts.
    Count,
    /// Appended to a vector.
    #[cfg(feature = "std")]
    Vec(&'a mut Vec<u8>),
    /// Into a caller's buffer, from its start; what does not fit is dropped and noted.
    Slice(&'a mut [u8]),
    /// Into a CRC-32.
    Crc(&'a mut crc32fast::Hasher),
}

/// Little-endian writer. [`Writer::counter`] only counts, so the size of a state is known
/// without allocating (the C ABI's size query) and always equals what a real write gives;
/// [`Writer::into_slice`] writes into a caller's buffer (no heap).
pub struct Writer<'a> {
    out: Sink<'a>,
    len: usize,
    overflow: bool,
}

impl<'a> Writer<'a> {
    /// Append to `out`.
    #[cfg(feature = "std")]
    pub fn new(out: &'a mut Vec<u8>) -> Self {
        Self {
            out: Sink::Vec(out),
            len: 0,
            overflow: false,
        }
    }

    /// Write into `out` from its start ([`Writer::overflowed`] tells whether all fitted).
    pub fn into_slice(out: &'a mut [u8]) -> Self {
        Self {
            out: Sink::Slice(out),
            len: 0,
            overflow: false,
        }
    }

    /// Feed the bytes to the CRC-32 `h`.
    pub fn into_crc(h: &'a mut crc32fast::Hasher) -> Self {
        Self {
            out: Sink::Crc(h),
            len: 0,
            overflow: false,
        }
    }

    /// A writer that stores nothing and counts the bytes.
    pub fn counter() -> Writer<'static> {
        Writer {
            out: Sink::Count,
            len: 0,
            overflow: false,
        }
    }

    /// Bytes written so far by this writer.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether nothing was written yet.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether bytes were dropped because the buffer of [`Writer::into_slice`] was full.
    pub fn overflowed(&self) -> bool {
        self.overflow
    }

    /// Raw bytes.
    pub fn bytes(&mut self, b: &[u8]) {
        match &mut self.out {
            Sink::Count => {}
            #[cfg(feature = "std")]
            Sink::Vec(v) => v.extend_from_slice(b),
            Sink::Slice(s) => match s.get_mut(self.len..self.len.saturating_add(b.len())) {
                // the length test lets the compiler drop copy_from_slice's panic
                Some(d) if d.len() == b.len() => d.copy_from_slice(b),
                _ => self.overflow = true,
            },
            Sink::Crc(h) => h.update(b),
        }
        self.len = self.len.saturating_add(b.len());
    }

    /// A 4-byte ASCII section tag (checked by [`Reader::tag`]).
    pub fn tag(&mut self, t: &[u8; 4]) {
        self.bytes(t);
    }

    /// One byte.
    pub fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }

    /// `false` = 0, `true` = 1.
    pub fn bool(&mut self, v: bool) {
        self.u8(u8::from(v));
    }

    /// 4 bytes LE.
    pub fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    /// 4 bytes LE.
    pub fn i32(&mut self, v: i32) {
        self.bytes(&v.to_le_bytes());
    }

    /// 8 bytes LE.
    pub fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }

    /// 8 bytes LE (two's complement).
    pub fn i64(&mut self, v: i64) {
        self.bytes(&v.to_le_bytes());
    }

    /// A count or index, as `u64`.
    pub fn usize(&mut self, v: usize) {
        self.u64(v as u64);
    }

    /// The IEEE-754 bits, 8 bytes LE.
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }

    /// A fixed-size matrix or vector, column by column.
    pub fn matrix<const R: usize, const C: usize>(&mut self, m: &SMatrix<f64, R, C>) {
        for v in m.iter() {
            self.f64(*v);
        }
    }

    /// A presence flag (`0` or `1`) followed by the matrix, or by zeros in its place: the
    /// size does not depend on whether the value is there.
    pub fn opt_matrix<const R: usize, const C: usize>(&mut self, m: Option<&SMatrix<f64, R, C>>) {
        self.bool(m.is_some());
        match m {
            Some(m) => self.matrix(m),
            None => self.matrix(&SMatrix::<f64, R, C>::zeros()),
        }
    }
}

/// Bounds-checked little-endian reader: every read names what it reads, so a truncated or
/// malformed state is refused with the field and offset, never a panic.
pub struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// Read `bytes` from the start.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, pos: 0 }
    }

    /// Current offset.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }

    /// The next `n` raw bytes.
    pub fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], StateError> {
        let end = self.pos.checked_add(n).filter(|e| *e <= self.bytes.len());
        match end.and_then(|e| self.bytes.get(self.pos..e)) {
            Some(b) => {
                self.pos += n;
                Ok(b)
            }
            None => Err(refuse(crate::msg!(
                "truncated: {what} needs {n} bytes at offset {}, {} left",
                self.pos,
                self.remaining()
            ))),
        }
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], StateError> {
        let b = self.take(N, what)?;
        let mut a = [0u8; N];
        a.copy_from_slice(b);
        Ok(a)
    }

    /// A section tag, which must be `t`.
    pub fn tag(&mut self, t: &[u8; 4]) -> Result<(), StateError> {
        let at = self.pos;
        let got = self.array::<4>("section tag")?;
        if &got == t {
            Ok(())
        } else {
            Err(refuse(crate::msg!(
                "expected section \"{}\" at offset {at}, found {:?}",
                core::str::from_utf8(t).unwrap_or("?"),
                core::str::from_utf8(&got).unwrap_or("?")
            )))
        }
    }

    /// One byte.
    pub fn u8(&mut self, what: &str) -> Result<u8, StateError> {
        Ok(self.array::<1>(what)?[0])
    }

    /// A byte that must be 0 or 1.
    pub fn bool(&mut self, what: &str) -> Result<bool, StateError> {
        let at = self.pos;
        match self.u8(what)? {
            0 => Ok(false),
            1 => Ok(true),
            v => Err(refuse(crate::msg!(
                "{what} at offset {at} must be 0 or 1 (got {v})"
            ))),
        }
    }

    /// 4 bytes LE.
    pub fn u32(&mut self, what: &str) -> Result<u32, StateError> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    /// 4 bytes LE.
    pub fn i32(&mut self, what: &str) -> Result<i32, StateError> {
        Ok(i32::from_le_bytes(self.array(what)?))
    }

    /// 8 bytes LE.
    pub fn u64(&mut self, what: &str) -> Result<u64, StateError> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }

    /// 8 bytes LE.
    pub fn i64(&mut self, what: &str) -> Result<i64, StateError> {
        Ok(i64::from_le_bytes(self.array(what)?))
    }

    /// A `u64` count or index that must fit `usize`.
    pub fn usize(&mut self, what: &str) -> Result<usize, StateError> {
        let v = self.u64(what)?;
        usize::try_from(v)
            .map_err(|_| refuse(crate::msg!("{what} = {v} does not fit this machine")))
    }

    /// A count that must equal `expected` (a size the configuration fixes).
    pub fn count(&mut self, what: &str, expected: usize) -> Result<(), StateError> {
        let n = self.u64(what)?;
        if n == expected as u64 {
            Ok(())
        } else {
            Err(refuse(crate::msg!(
                "{what} is {n} in the state, {expected} in this configuration"
            )))
        }
    }

    /// An `f64` from its bits.
    pub fn f64(&mut self, what: &str) -> Result<f64, StateError> {
        Ok(f64::from_bits(self.u64(what)?))
    }

    /// A finite `f64`.
    pub fn finite(&mut self, what: &str) -> Result<f64, StateError> {
        let v = self.f64(what)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(refuse(crate::msg!("{what} must be finite (got {v})")))
        }
    }

    /// A fixed-size matrix or vector, column by column.
    pub fn matrix<const R: usize, const C: usize>(
        &mut self,
        what: &str,
    ) -> Result<SMatrix<f64, R, C>, StateError> {
        let mut m = SMatrix::<f64, R, C>::zeros();
        for v in m.iter_mut() {
            *v = self.f64(what)?;
        }
        Ok(m)
    }

    /// A matrix whose entries must all be finite (an estimate, a covariance).
    pub fn finite_matrix<const R: usize, const C: usize>(
        &mut self,
        what: &str,
    ) -> Result<SMatrix<f64, R, C>, StateError> {
        let m = self.matrix::<R, C>(what)?;
        if m.iter().all(|v| v.is_finite()) {
            Ok(m)
        } else {
            Err(refuse(crate::msg!("{what} must be finite")))
        }
    }

    /// A presence flag and a matrix ([`Writer::opt_matrix`]); `None` when the flag is 0.
    pub fn opt_matrix<const R: usize, const C: usize>(
        &mut self,
        what: &str,
    ) -> Result<Option<SMatrix<f64, R, C>>, StateError> {
        let present = self.bool(what)?;
        let m = self.matrix(what)?;
        Ok(present.then_some(m))
    }

    /// Everything must have been read.
    pub fn finish(&self) -> Result<(), StateError> {
        match self.remaining() {
            0 => Ok(()),
            n => Err(refuse(crate::msg!(
                "{n} unexpected bytes after the last field (offset {})",
                self.pos
            ))),
        }
    }
}

/// Length of the envelope's header for an identity block of `ident_len` bytes: magic (8),
/// format version (4), identity, payload length (8), CRC-32 (4).
pub const fn header_len(ident_len: usize) -> usize {
    8 + 4 + ident_len + 8 + 4
}

#[cfg(feature = "std")]
/// Append an envelope to `out`: `magic`, `version` (u32 LE), the identity block `ident`,
/// the payload length (u64 LE), the CRC-32 (IEEE, u32 LE) of every header byte before it
/// and of the payload, then the payload written by `payload`.
pub fn seal(
    out: &mut Vec<u8>,
    magic: &[u8; 8],
    version: u32,
    ident: &[u8],
    payload: impl FnOnce(&mut Writer<'_>),
) {
    let start = out.len();
    out.extend_from_slice(magic);
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(ident);
    let len_at = out.len();
    out.extend_from_slice(&0u64.to_le_bytes());
    let crc_at = out.len();
    out.extend_from_slice(&0u32.to_le_bytes());
    let body = out.len();
    payload(&mut Writer::new(out));
    let n = (out.len() - body) as u64;
    if let Some(s) = out.get_mut(len_at..crc_at) {
        s.copy_from_slice(&n.to_le_bytes());
    }
    let mut h = crc32fast::Hasher::new();
    h.update(out.get(start..crc_at).unwrap_or_default());
    h.update(out.get(body..).unwrap_or_default());
    let crc = h.finalize();
    if let Some(s) = out.get_mut(crc_at..body) {
        s.copy_from_slice(&crc.to_le_bytes());
    }
}

/// [`seal`] into the start of `out` (no heap): the envelope's length, or `None` (and
/// `out` partly written) when it does not fit.
pub fn seal_into(
    out: &mut [u8],
    magic: &[u8; 8],
    version: u32,
    ident: &[u8],
    payload: impl FnOnce(&mut Writer<'_>),
) -> Option<usize> {
    let len_at = 12 + ident.len();
    let crc_at = len_at + 8;
    let body = crc_at + 4;
    let (head, rest) = (out.len() >= body).then(|| out.split_at_mut(body))?;
    let mut w = Writer::into_slice(head);
    w.bytes(magic);
    w.u32(version);
    w.bytes(ident);
    let mut w = Writer::into_slice(rest);
    payload(&mut w);
    if w.overflowed() {
        return None;
    }
    let n = w.len();
    head.get_mut(len_at..crc_at)?
        .copy_from_slice(&(n as u64).to_le_bytes());
    let mut h = crc32fast::Hasher::new();
    h.update(head.get(..crc_at)?);
    h.update(rest.get(..n)?);
    head.get_mut(crc_at..body)?
        .copy_from_slice(&h.finalize().to_le_bytes());
    Some(body + n)
}

/// The size [`seal`] gives for `ident_len` identity bytes and what `payload` writes
/// (counted, nothing stored).
pub fn sealed_len(ident_len: usize, payload: impl FnOnce(&mut Writer<'_>)) -> usize {
    let mut w = Writer::counter();
    payload(&mut w);
    header_len(ident_len) + w.len()
}

/// What [`open`] found in a valid envelope.
#[derive(Debug, Clone, Copy)]
pub struct Opened<'a> {
    /// The identity block.
    pub ident: &'a [u8],
    /// The payload (its length and checksum verified).
    pub payload: &'a [u8],
}

/// Check an envelope made by [`seal`] and return its identity block and payload. Refused,
/// in this order: too short for a header, another `magic` (`what` names the expected kind,
/// `other` lists magics of other relnav states with their names for a clearer message),
/// another format `version`, a payload length that disagrees with the bytes present
/// (truncated or trailing bytes), a CRC-32 mismatch (corrupted).
pub fn open<'a>(
    bytes: &'a [u8],
    magic: &[u8; 8],
    version: u32,
    ident_len: usize,
    what: &str,
    other: &[(&[u8; 8], &str)],
) -> Result<Opened<'a>, StateError> {
    let hl = header_len(ident_len);
    let mut r = Reader::new(bytes);
    let got = r.take(8, "magic").map_err(|_| {
        refuse(crate::msg!(
            "truncated: {} bytes, not even the 8-byte magic of {what}",
            bytes.len()
        ))
    })?;
    if got != magic {
        if let Some((_, name)) = other.iter().find(|(m, _)| m.as_slice() == got) {
            return Err(refuse(crate::msg!("this is {name}, not {what}")));
        }
        return Err(refuse(crate::msg!(
            "not {what}: magic {:?}, expected {:?}",
            core::str::from_utf8(got).unwrap_or("?"),
            core::str::from_utf8(magic).unwrap_or("?")
        )));
    }
    let v = r.u32("format version").map_err(|_| {
        refuse(crate::msg!(
            "truncated: {} bytes, header of {what} is {hl}",
            bytes.len()
        ))
    })?;
    if v != version {
        return Err(refuse(crate::msg!(
            "{what} has format version {v}; this build of relnav {} reads version {version} only",
            crate::VERSION
        )));
    }
    if bytes.len() < hl {
        return Err(refuse(crate::msg!(
            "truncated: {} bytes, the header of {what} alone is {hl}",
            bytes.len()
        )));
    }
    let ident = r.take(ident_len, "identity")?;
    let n = r.u64("payload length")?;
    let crc = r.u32("checksum")?;
    let present = (bytes.len() - hl) as u64;
    if present < n {
        return Err(refuse(crate::msg!(
            "truncated: the header declares {n} payload bytes, {present} are present"
        )));
    }
    if present > n {
        return Err(refuse(crate::msg!(
            "{} unexpected bytes after the declared payload of {n} bytes",
            present - n
        )));
    }
    let payload = bytes.get(hl..).unwrap_or_default();
    let mut h = crc32fast::Hasher::new();
    h.update(bytes.get(..hl - 4).unwrap_or_default());
    h.update(payload);
    let actual = h.finalize();
    if actual != crc {
        return Err(refuse(crate::msg!(
            "checksum mismatch (CRC-32 {actual:08x}, header says {crc:08x}): {what} is corrupted"
        )));
    }
    Ok(Opened { ident, payload })
}

/// CRC-32 (IEEE) of `bytes`: the configuration fingerprint of a state header.
pub fn crc32(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2x3;

    const M: &[u8; 8] = b"TESTMAGC";

    fn payload(w: &mut Writer<'_>) {
        w.tag(b"ABCD");
        w.u8(7);
        w.bool(true);
        w.u32(0xdead_beef);
        w.i32(-2);
        w.u64(u64::MAX - 1);
        w.i64(-5);
        w.f64(-0.0);
        w.f64(f64::from_bits(0x7ff8_0000_0000_1234));
        w.matrix(&Matrix2x3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0));
        w.opt_matrix::<2, 3>(None);
    }

    fn sample() -> Vec<u8> {
        let mut out = Vec::new();
        seal(&mut out, M, 3, b"id", payload);
        out
    }

    /// `seal_into` writes what `seal` appends; a buffer one byte short is refused.
    #[test]
    fn seal_into_a_buffer_is_seal() {
        let b = sample();
        let mut buf = vec![0xAA; b.len() + 3];
        assert_eq!(seal_into(&mut buf, M, 3, b"id", payload), Some(b.len()));
        assert_eq!(&buf[..b.len()], &b[..]);
        let mut short = vec![0; b.len() - 1];
        assert_eq!(seal_into(&mut short, M, 3, b"id", payload), None);
    }

    #[test]
    fn round_trip_is_bit_exact_and_little_endian() {
        let b = sample();
        assert_eq!(&b[..8], M);
        assert_eq!(&b[8..12], &3u32.to_le_bytes());
        assert_eq!(&b[12..14], b"id");
        let o = open(&b, M, 3, 2, "a test state", &[]).unwrap();
        assert_eq!(o.ident, b"id");
        let mut r = Reader::new(o.payload);
        r.tag(b"ABCD").unwrap();
        assert_eq!(r.u8("a").unwrap(), 7);
        assert!(r.bool("b").unwrap());
        assert_eq!(r.u32("c").unwrap(), 0xdead_beef);
        assert_eq!(r.i32("d").unwrap(), -2);
        assert_eq!(r.u64("e").unwrap(), u64::MAX - 1);
        assert_eq!(r.i64("f").unwrap(), -5);
        assert_eq!(r.f64("g").unwrap().to_bits(), (-0.0f64).to_bits());
        assert_eq!(r.f64("h").unwrap().to_bits(), 0x7ff8_0000_0000_1234);
        // column by column: 1, 4, 2, 5, 3, 6
        let at = r.position();
        assert_eq!(&o.payload[at..at + 8], &1.0f64.to_le_bytes());
        assert_eq!(&o.payload[at + 8..at + 16], &4.0f64.to_le_bytes());
        let m = r.matrix::<2, 3>("m").unwrap();
        assert_eq!(m, Matrix2x3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0));
        assert_eq!(r.opt_matrix::<2, 3>("o").unwrap(), None);
        r.finish().unwrap();
        // the counter agrees with the writer
        let n = sealed_len(2, |w| {
            w.tag(b"ABCD");
            w.u8(7);
            w.bool(true);
            w.u32(0);
            w.i32(0);
            w.u64(0);
            w.i64(0);
            w.f64(0.0);
            w.f64(0.0);
            w.matrix(&Matrix2x3::<f64>::zeros());
            // present or not, the same size
            w.opt_matrix(Some(&Matrix2x3::<f64>::zeros()));
        });
        assert_eq!(n, b.len());
    }

    #[test]
    fn every_truncation_and_every_flipped_bit_is_refused() {
        let b = sample();
        for len in 0..b.len() {
            let e = open(&b[..len], M, 3, 2, "a test state", &[]).unwrap_err();
            assert!(e.0.contains("truncated"), "length {len}: {e}");
        }
        for i in 0..b.len() {
            for bit in 0..8 {
                let mut c = b.clone();
                c[i] ^= 1 << bit;
                assert!(
                    open(&c, M, 3, 2, "a test state", &[]).is_err(),
                    "byte {i} bit {bit}"
                );
            }
        }
        let mut longer = b.clone();
        longer.push(0);
        assert!(open(&longer, M, 3, 2, "a test state", &[])
            .unwrap_err()
            .0
            .contains("unexpected bytes"));
        let e = open(&b, M, 4, 2, "a test state", &[]).unwrap_err();
        assert!(e.0.contains("format version 3"), "{e}");
        let e = open(&b, b"OTHERMAG", 3, 2, "X", &[(M, "a test state")]).unwrap_err();
        assert_eq!(e.0, "this is a test state, not X");
    }

    #[test]
    fn reader_refuses_bad_fields() {
        let mut r = Reader::new(&[2]);
        assert!(r.bool("flag").is_err());
        let mut r = Reader::new(&[1, 0, 0]);
        assert!(r
            .u32("x")
            .unwrap_err()
            .0
            .contains("truncated: x needs 4 bytes"));
        let nan = f64::NAN.to_le_bytes();
        assert!(Reader::new(&nan).finite("v").is_err());
        let three = 3u64.to_le_bytes();
        assert!(Reader::new(&three).count("particles", 4).is_err());
        assert!(Reader::new(&three).count("particles", 3).is_ok());
        assert!(Reader::new(&[0]).finish().is_err());
    }
}
