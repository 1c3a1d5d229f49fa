//! The text of a logger file. Loggers write UTF-8, Windows code pages (a `µ` or `°` in a
//! unit as one byte) and, from Windows tools, UTF-16 with a byte-order mark; all three
//! are read. A file with control bytes other than tab, CR, LF and form feed is not text
//! (binary data, or UTF-16 without its mark): an error at the first such byte.

use std::path::Path;

use towride_mbs::input::InputError;

use super::csv_reader::err;

/// `bytes` of `file` as text: UTF-8 (a BOM dropped), UTF-16 LE/BE after its BOM, else
/// Latin-1 (one byte, one character; the units in a Windows-1252 export read right).
pub(super) fn decode(file: &Path, bytes: &[u8]) -> Result<String, InputError> {
    let text = match bytes {
        [0xFF, 0xFE, rest @ ..] => utf16(file, rest, u16::from_le_bytes)?,
        [0xFE, 0xFF, rest @ ..] => utf16(file, rest, u16::from_be_bytes)?,
        _ => match std::str::from_utf8(bytes) {
            Ok(s) => s.trim_start_matches('\u{feff}').to_string(),
            Err(_) => bytes.iter().map(|&b| b as char).collect(),
        },
    };
    if let Some((i, c)) = text.char_indices().find(|(_, c)| is_binary(*c)) {
        let line = text[..i].matches('\n').count() + 1;
        let column = text[..i]
            .rsplit('\n')
            .next()
            .map_or(0, |l| l.chars().count())
            + 1;
        return Err(err(
            file,
            Some(line),
            Some(column),
            "encoding",
            format!(
                "control character U+{:04X}: not a text file (binary data, or UTF-16 \
                 without a byte-order mark); export the recording as CSV text",
                c as u32
            ),
        ));
    }
    Ok(text)
}

/// A control character no text export writes.
fn is_binary(c: char) -> bool {
    c.is_control() && !matches!(c, '\t' | '\n' | '\r' | '\u{c}') && (c as u32) < 0x80
}

fn utf16(file: &Path, bytes: &[u8], unit: fn([u8; 2]) -> u16) -> Result<String, InputError> {
    let units = bytes.chunks_exact(2).map(|p| unit([p[0], p[1]]));
    let mut out = String::with_capacity(bytes.len() / 2);
    for (k, c) in char::decode_utf16(units).enumerate() {
        match c {
            Ok(c) => out.push(c),
            Err(e) => {
                let line = out.matches('\n').count() + 1;
                return Err(err(
                    file,
                    Some(line),
                    None,
                    "encoding",
                    format!(
                        "UTF-16 unit {k} (0x{:04X}) is an unpaired surrogate: the file is \
                         cut or not UTF-16",
                        e.unpaired_surrogate()
                    ),
                ));
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_three_encodings_and_refuses_binary() {
        let f = Path::new("log.csv");
        assert_eq!(
            decode(f, "t [s];a [µm]\n".as_bytes()).unwrap(),
            "t [s];a [µm]\n"
        );
        assert_eq!(decode(f, b"a [\xB5m]\n").unwrap(), "a [µm]\n");
        let mut le = vec![0xFF, 0xFE];
        "x,y\n1,2\n"
            .encode_utf16()
            .for_each(|u| le.extend(u.to_le_bytes()));
        assert_eq!(decode(f, &le).unwrap(), "x,y\n1,2\n");
        let mut be = vec![0xFE, 0xFF];
        "é\n"
            .encode_utf16()
            .for_each(|u| be.extend(u.to_be_bytes()));
        assert_eq!(decode(f, &be).unwrap(), "é\n");
        let e = decode(f, b"time,a\n0,\x001\n").unwrap_err();
        assert_eq!((e.line, e.column), (Some(2), Some(3)));
        assert!(decode(f, &[0xFF, 0xFE, 0x00, 0xD8, 0x41, 0x00]).is_err());
    }
}
