//! NumPy `.npz` archives: a zip file with one `.npy` member per array (`x.npy` holds
//! the array `x`). [`Npz::open`] reads the archive's directory (the zip crate) and
//! every member's NPY header, and [`Npz::read`] reads one member's data only when it is
//! asked for, so an archive may hold arrays that cannot be columns (a 0-d text
//! description, a 3-D array) as long as nothing asks for them.
//!
//! A stored member (`np.savez`) is read in one pass straight from the file at its data
//! offset ([`super::npy::read_data`]); its CRC-32 is computed on the way (crc32fast,
//! SIMD, well above memory speed) and compared with the directory's, which is what
//! NumPy does too: `numpy.load` reads members through Python's zipfile, which checks
//! the CRC of every member read to its end, stored or deflated. A deflated member
//! (`np.savez_compressed`) is inflated through zip's reader, which checks its CRC, and
//! read as it is inflated (never whole into memory: a member of a few MB can claim
//! gigabytes, and the values are checked against the memory budget before they are
//! allocated). A member's data must lie inside the file before any of
//! it is read.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use zip::{CompressionMethod, ZipArchive};

use crate::error::Result;
use crate::io::arrays::NamedArray;
use crate::io::npy::{Header, data_error, read_data, read_header, require_data};
use crate::io::parts::{Crc, Source, read_parts};
use crate::io::scatter::Target;

/// Elements converted per block when a member is read into place: 128 KiB of f64, so
/// the block stays in cache while its columns are written out.
const INTO_BLOCK: usize = 1 << 14;

/// Where a stored member's bytes lie in the file.
#[derive(Debug, Clone, Copy)]
struct Stored {
    /// Offset of the member's first byte (its NPY header).
    start: u64,
    /// The member's length.
    size: u64,
    /// The CRC-32 the directory gives.
    crc: u32,
}

/// One array of the archive: its name, its header (or why it cannot be columns), and
/// where its bytes are.
#[derive(Debug, Clone)]
pub(crate) struct Member {
    /// The array's name (the member's name without `.npy`).
    pub name: String,
    /// Its NPY header, or why it cannot be table columns.
    pub header: std::result::Result<Header, String>,
    /// Its index in the archive's directory.
    index: usize,
    /// Where its bytes are when stored; `None` when compressed.
    stored: Option<Stored>,
}

/// A `.npz` archive's arrays, read on demand.
#[derive(Debug, Clone)]
pub(crate) struct Npz {
    file: String,
    path: PathBuf,
    /// Sorted by name.
    pub members: Vec<Member>,
}

/// A reader that counts the bytes it passes on.
struct Counted<R> {
    inner: R,
    count: u64,
}

impl<R: Read> Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.count += n as u64;
        Ok(n)
    }
}

impl Npz {
    /// Reads the directory of the archive at `path` and each member's header.
    pub fn open(path: &Path) -> Result<Npz> {
        let file = path.display().to_string();
        let error = |e: &dyn std::fmt::Display| data_error(&file, "", e);
        super::require_data_file(path)?;
        let opened = File::open(path).map_err(|e| error(&e))?;
        let length = opened.metadata().map_err(|e| error(&e))?.len();
        let mut archive = ZipArchive::new(BufReader::new(opened))
            .map_err(|e| error(&format!("not an .npz (zip) archive: {e}")))?;
        let mut raw = File::open(path).map_err(|e| error(&e))?;
        let mut members = Vec::with_capacity(archive.len());
        for index in 0..archive.len() {
            let entry = archive.by_index_raw(index).map_err(|e| error(&e))?;
            if entry.is_dir() {
                continue;
            }
            let name = entry.name();
            let name = name.strip_suffix(".npy").unwrap_or(name).to_string();
            let stored = (entry.compression() == CompressionMethod::Stored).then(|| Stored {
                start: entry.data_start(),
                size: entry.compressed_size(),
                crc: entry.crc32(),
            });
            drop(entry);
            let header = match stored {
                Some(s) if s.start.checked_add(s.size).is_none_or(|end| end > length) => {
                    Err(format!(
                        "the archive is truncated: member '{name}.npy' needs bytes {} to {}, the file has {length}",
                        s.start,
                        s.start.saturating_add(s.size)
                    ))
                }
                Some(s) => {
                    raw.seek(SeekFrom::Start(s.start)).map_err(|e| error(&e))?;
                    read_header(BufReader::new((&mut raw).take(s.size)))
                }
                None => match archive.by_index(index) {
                    Ok(inflating) => read_header(BufReader::new(inflating)),
                    Err(e) => Err(e.to_string()),
                },
            };
            members.push(Member {
                name,
                header,
                index,
                stored,
            });
        }
        members.sort_by(|a, b| a.name.cmp(&b.name));
        Ok(Npz {
            file,
            path: path.to_path_buf(),
            members,
        })
    }

    /// The archive, as error messages name it.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// Reads the data of `member` (whose header is usable: `header`).
    pub fn read(&self, member: &Member, header: &Header) -> Result<NamedArray> {
        let (file, name) = (self.file.as_str(), member.name.as_str());
        let error = |e: &dyn std::fmt::Display| data_error(file, name, e);
        let Some(stored) = member.stored else {
            // Inflated as it is read, never whole into memory: a member of a few MB can
            // claim gigabytes, which `read_data` checks against the budget first; the
            // size the directory gives bounds the data, and a member that ends sooner is
            // an error of `read_data` (its CRC is checked by zip's reader at the end).
            let opened = File::open(&self.path).map_err(|e| error(&e))?;
            let mut archive = ZipArchive::new(BufReader::new(opened)).map_err(|e| error(&e))?;
            let inflating = archive
                .by_index(member.index)
                .map_err(|e| error(&format!("inflating '{name}.npy': {e}")))?;
            let size = inflating.size();
            let mut reader = BufReader::with_capacity(
                1 << 16,
                Counted {
                    inner: inflating,
                    count: 0,
                },
            );
            read_header(&mut reader).map_err(|e| error(&e))?;
            // What the BufReader took from the member but has not handed out yet.
            let consumed = reader.get_ref().count - reader.buffer().len() as u64;
            let available = size.saturating_sub(consumed);
            let array = read_data(&mut reader, header, available, name, file)?;
            std::io::copy(&mut reader, &mut std::io::sink())
                .map_err(|e| error(&format!("inflating '{name}.npy': {e}")))?;
            return Ok(array);
        };
        self.read_stored(member, stored, |reader, available| {
            read_data(reader, header, available, name, file)
        })
    }

    /// Whether `member` is stored (not deflated) and its header's data fit inside it:
    /// what [`Npz::read_into`] reads, with nothing of the header's size allocated for a
    /// member that cannot hold it.
    pub fn can_read_into(member: &Member) -> bool {
        match (&member.stored, &member.header) {
            (Some(stored), Ok(header)) => header.data_bytes().is_some_and(|n| n <= stored.size),
            _ => false,
        }
    }

    /// Reads the data of the stored `member` (whose header is `header`) straight into
    /// `targets`, in blocks that stay in cache ([`Layout::scatter`]), a large member in
    /// parts read by up to `threads` threads ([`read_parts`]), with the checks of
    /// [`Npz::read`]: the data inside the member, every value finite, its CRC-32. A
    /// member that is not stored is an error (use [`Npz::read`]).
    ///
    /// [`Layout::scatter`]: crate::io::arrays::Layout::scatter
    pub fn read_into(
        &self,
        member: &Member,
        header: &Header,
        targets: &mut [Target<'_>],
        threads: usize,
    ) -> Result<()> {
        let (file, name) = (self.file.as_str(), member.name.as_str());
        let Some(stored) = member.stored else {
            return Err(data_error(
                file,
                name,
                "a compressed member cannot be read in place",
            ));
        };
        let error = |e: &dyn std::fmt::Display| data_error(file, name, e);
        // The header read unbuffered (npyz reads exactly its bytes, in a few reads): the
        // file is then at the first data byte, and the hasher has seen the header only.
        let mut opened = File::open(&self.path).map_err(|e| error(&e))?;
        opened
            .seek(SeekFrom::Start(stored.start))
            .map_err(|e| error(&e))?;
        let mut head = Crc {
            inner: (&mut opened).take(stored.size),
            hasher: crc32fast::Hasher::new(),
        };
        read_header(&mut head).map_err(|e| error(&e))?;
        let consumed = stored.size - head.inner.limit();
        let mut crc = head.hasher;
        require_data(header, stored.size - consumed, name, file)?;
        // cannot fail: require_data checked that the data bytes fit the member
        let data = header.data_bytes().expect("checked by require_data");
        let start = stored.start + consumed;
        let source = Source {
            opened,
            path: &self.path,
            start,
        };
        let data_crc = read_parts(source, header, INTO_BLOCK, threads, targets, name, file)?;
        crc.combine(&data_crc);
        // The CRC covers the whole member, whatever follows the data.
        let trailing = stored.size - consumed - data;
        if trailing > 0 {
            let mut tail = File::open(&self.path).map_err(|e| error(&e))?;
            tail.seek(SeekFrom::Start(start + data))
                .map_err(|e| error(&e))?;
            let mut rest = Crc {
                inner: tail.take(trailing),
                hasher: crc32fast::Hasher::new(),
            };
            std::io::copy(&mut rest, &mut std::io::sink()).map_err(|e| error(&e))?;
            crc.combine(&rest.hasher);
        }
        check_crc(crc.finalize(), stored, name, file)
    }

    /// Opens the stored `member`, reads its header, hands `body` the reader at its first
    /// data byte and the bytes of the member after the header, then checks the CRC-32
    /// of the whole member.
    fn read_stored<T>(
        &self,
        member: &Member,
        stored: Stored,
        body: impl FnOnce(&mut BufReader<Crc<std::io::Take<File>>>, u64) -> Result<T>,
    ) -> Result<T> {
        let (file, name) = (self.file.as_str(), member.name.as_str());
        let error = |e: &dyn std::fmt::Display| data_error(file, name, e);
        let mut opened = File::open(&self.path).map_err(|e| error(&e))?;
        opened
            .seek(SeekFrom::Start(stored.start))
            .map_err(|e| error(&e))?;
        let mut reader = BufReader::with_capacity(
            1 << 16,
            Crc {
                inner: opened.take(stored.size),
                hasher: crc32fast::Hasher::new(),
            },
        );
        read_header(&mut reader).map_err(|e| error(&e))?;
        // What the BufReader took from the member but has not handed out yet.
        let consumed = stored.size - reader.get_ref().inner.limit() - reader.buffer().len() as u64;
        let value = body(&mut reader, stored.size - consumed)?;
        // The CRC covers the whole member, whatever follows the data.
        std::io::copy(&mut reader, &mut std::io::sink()).map_err(|e| error(&e))?;
        check_crc(reader.into_inner().hasher.finalize(), stored, name, file)?;
        Ok(value)
    }
}

/// `Ok` when `crc`, computed over the whole member `name`, is the one the archive's
/// directory gives.
fn check_crc(crc: u32, stored: Stored, name: &str, file: &str) -> Result<()> {
    if crc == stored.crc {
        return Ok(());
    }
    Err(data_error(
        file,
        name,
        format!(
            "member '{name}.npy' is damaged: its CRC-32 is {crc:08x}, the archive's directory says {:08x}",
            stored.crc
        ),
    ))
}
