//! Readable messages that need no heap: [`Message`] and the [`msg!`](crate::msg) macro.
//!
//! With the `std` feature a message is a `String` formatted with its values, as
//! `format!` writes it. Without it (the flight build: no heap, no float formatting, whose
//! code in `core::fmt` can panic) a message is a fixed-capacity buffer of text: the
//! format string with each `{...}` argument written as `?`, and the texts a caller appends
//! with [`Message::push`] (a parameter's name, for one). The same error then reads
//! "sigma_pos0 must be finite and > 0 (got -1)" in the full library and "sigma_pos0 must
//! be finite and > 0 (got ?)" in the flight library.

#[cfg(feature = "std")]
use std::string::String;

/// The capacity of a message without `std`, in bytes; longer text is cut at a character
/// boundary.
pub const MESSAGE_CAPACITY: usize = 160;

/// A readable message (see the module documentation).
#[derive(Clone, PartialEq, Eq)]
pub struct Message {
    #[cfg(feature = "std")]
    text: String,
    #[cfg(not(feature = "std"))]
    buf: [u8; MESSAGE_CAPACITY],
    #[cfg(not(feature = "std"))]
    len: usize,
}

impl Message {
    /// The empty message.
    pub const fn new() -> Self {
        Self {
            #[cfg(feature = "std")]
            text: String::new(),
            #[cfg(not(feature = "std"))]
            buf: [0; MESSAGE_CAPACITY],
            #[cfg(not(feature = "std"))]
            len: 0,
        }
    }

    /// `text` as a message.
    pub fn text(text: &str) -> Self {
        let mut m = Self::new();
        m.push(text);
        m
    }

    /// The texts one after the other.
    pub fn concat(parts: &[&str]) -> Self {
        let mut m = Self::new();
        for p in parts {
            m.push(p);
        }
        m
    }

    /// Appends `text` (without `std`: as much of it as fits, whole characters).
    pub fn push(&mut self, text: &str) -> &mut Self {
        #[cfg(feature = "std")]
        self.text.push_str(text);
        #[cfg(not(feature = "std"))]
        {
            let room = MESSAGE_CAPACITY - self.len;
            let mut n = text.len().min(room);
            while !text.is_char_boundary(n) {
                n -= 1;
            }
            if let (Some(dst), Some(src)) = (
                self.buf.get_mut(self.len..self.len + n),
                text.as_bytes().get(..n),
            ) {
                dst.copy_from_slice(src);
                self.len += n;
            }
        }
        self
    }

    /// `text` and then this message.
    pub fn prefixed(&self, text: &str) -> Self {
        let mut m = Self::text(text);
        m.push(self.as_str());
        m
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        #[cfg(feature = "std")]
        return &self.text;
        #[cfg(not(feature = "std"))]
        return self
            .buf
            .get(..self.len)
            .and_then(|b| core::str::from_utf8(b).ok())
            .unwrap_or("");
    }
}

impl Default for Message {
    fn default() -> Self {
        Self::new()
    }
}

impl core::ops::Deref for Message {
    type Target = str;
    fn deref(&self) -> &str {
        self.as_str()
    }
}

impl core::fmt::Debug for Message {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Debug::fmt(self.as_str(), f)
    }
}

impl core::fmt::Display for Message {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl PartialEq<str> for Message {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

impl PartialEq<&str> for Message {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

impl From<&str> for Message {
    fn from(text: &str) -> Self {
        Self::text(text)
    }
}

#[cfg(feature = "std")]
impl From<String> for Message {
    fn from(text: String) -> Self {
        Self { text }
    }
}

#[cfg(feature = "std")]
impl From<Message> for String {
    fn from(m: Message) -> Self {
        m.text
    }
}

/// The length of `fmt` with each `{...}` argument written as `?` and `{{`, `}}` as one
/// brace (the text [`msg!`](crate::msg) keeps without `std`).
#[doc(hidden)]
pub const fn template_len(fmt: &str) -> usize {
    let b = fmt.as_bytes();
    let (mut i, mut n) = (0, 0);
    while i < b.len() {
        let escaped = (b[i] == b'{' || b[i] == b'}') && i + 1 < b.len() && b[i + 1] == b[i];
        if escaped {
            i += 2;
        } else if b[i] == b'{' {
            while i < b.len() && b[i] != b'}' {
                i += 1;
            }
            i += 1;
        } else {
            i += 1;
        }
        n += 1;
    }
    n
}

/// `fmt` as [`template_len`] counts it, in `N` bytes.
#[doc(hidden)]
pub const fn template<const N: usize>(fmt: &str) -> [u8; N] {
    let b = fmt.as_bytes();
    let mut out = [0u8; N];
    let (mut i, mut n) = (0, 0);
    while i < b.len() && n < N {
        if b[i] == b'{' && i + 1 < b.len() && b[i + 1] == b'{' {
            out[n] = b'{';
            i += 2;
        } else if b[i] == b'}' && i + 1 < b.len() && b[i + 1] == b'}' {
            out[n] = b'}';
            i += 2;
        } else if b[i] == b'{' {
            while i < b.len() && b[i] != b'}' {
                i += 1;
            }
            out[n] = b'?';
            i += 1;
        } else {
            out[n] = b[i];
            i += 1;
        }
        n += 1;
    }
    out
}

/// A [`Message`] from a format string and its arguments: `format!` with `std`; without
/// it the format string with each argument written as `?` (worked out at compile time).
#[cfg(feature = "std")]
#[macro_export]
macro_rules! msg {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {
        $crate::message::Message::from(::std::format!($fmt $(, $arg)*))
    };
}

/// A [`Message`] from a format string and its arguments: `format!` with `std`; without
/// it the format string with each argument written as `?` (worked out at compile time).
#[cfg(not(feature = "std"))]
#[macro_export]
macro_rules! msg {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{
        #[allow(unreachable_code, clippy::diverging_sub_expression)]
        if false {
            $(let _ = &$arg;)*
        }
        const N: usize = $crate::message::template_len($fmt);
        const B: [u8; N] = $crate::message::template::<N>($fmt);
        $crate::message::Message::text(match ::core::str::from_utf8(&B) {
            Ok(s) => s,
            Err(_) => "",
        })
    }};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn template_writes_arguments_as_question_marks() {
        const F: &str = "{name} must lie in {lo}..={hi} (got {v:.3}) {{braces}}";
        const N: usize = template_len(F);
        let b = template::<N>(F);
        assert_eq!(
            core::str::from_utf8(&b),
            Ok("? must lie in ?..=? (got ?) {braces}")
        );
    }

    #[test]
    fn concat_joins_the_parts() {
        assert_eq!(Message::concat(&["a", ": ", "b"]), "a: b");
        assert_eq!(Message::concat(&[]), "");
    }

    #[test]
    fn push_appends_and_prefixed_prepends() {
        let mut m = Message::text("x");
        m.push(" must be finite");
        assert_eq!(m.prefixed("camera: ").as_str(), "camera: x must be finite");
    }
}
