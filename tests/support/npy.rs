//! NPY bytes written by hand for the reading tests: the magic, version 1.0, the header
//! dict padded with spaces to a multiple of 64 bytes (ending in a newline), then the
//! data as given (a test may cut it or claim more than it holds).

/// An NPY file of header `dict` followed by `data`.
pub fn npy_bytes(dict: &str, data: &[u8]) -> Vec<u8> {
    let mut header = dict.to_string();
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend_from_slice(data);
    bytes
}
