//! The server's certificate store (async-opcua's `pki` layout: `own/cert.der`,
//! `private/private.pem`, `trusted/`, `rejected/`). Its self-signed application instance
//! certificate is what the Basic256Sha256 endpoints sign and encrypt with, and what encrypts a
//! user-name token's password.
//!
//! Where: beside a SQLite database, in `FILE-opcua-pki/` (like SQLite's own `FILE-wal`), so
//! the certificate survives a restart and a client trusts it once; with PostgreSQL (or an
//! in-memory database) there is no file to sit beside, and a directory of the system's
//! temporary one is made for this process and removed when the server stops: each start
//! shows a new certificate.

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use opcua::crypto::{CertificateStore, X509Data};
use opcua::types::ApplicationDescription;

/// How long a certificate this server makes is valid; one with less than [`RENEW_BEFORE`] left
/// at a start is replaced.
const VALID_DAYS: u32 = 5 * 365;
const RENEW_BEFORE: Duration = Duration::from_secs(30 * 24 * 3600);

#[derive(Debug)]
pub struct Pki {
    pub dir: PathBuf,
    /// Made for this process: removed at [`Pki::close`].
    temporary: bool,
}

impl Pki {
    /// The directory for the database `sqlite_file` (None: not a file).
    pub fn beside(sqlite_file: Option<&Path>) -> Pki {
        match sqlite_file {
            Some(file) => {
                let mut name = file.file_name().unwrap_or_default().to_os_string();
                name.push("-opcua-pki");
                Pki { dir: file.with_file_name(name), temporary: false }
            }
            None => {
                let unique = uuid::Uuid::new_v4().simple().to_string();
                Pki { dir: std::env::temp_dir().join(format!("fivex-opcua-pki-{unique}")), temporary: true }
            }
        }
    }

    /// Removes a temporary directory.
    pub fn close(&self) {
        if self.temporary {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

/// Makes the certificate and its private key in `dir` unless a valid one is there (RSA key
/// generation: seconds; call off the async runtime's threads). The directory is the owner's
/// only: it holds the private key.
pub fn ensure_certificate(
    dir: &Path,
    application: ApplicationDescription,
    addresses: Vec<String>,
) -> Result<(), String> {
    create_private_dir(dir).map_err(|e| format!("--opcua: cannot create {}: {e}", dir.display()))?;
    let store = CertificateStore::new(dir);
    let current = store.read_own_cert().ok().and_then(|cert| cert.not_after().ok());
    let renew_after = SystemTime::now() + RENEW_BEFORE;
    let valid = current.is_some_and(|not_after| {
        u64::try_from(not_after.timestamp())
            .is_ok_and(|s| SystemTime::UNIX_EPOCH + Duration::from_secs(s) > renew_after)
    });
    if valid && store.read_own_pkey().is_ok() {
        return Ok(());
    }
    let mut data = X509Data::from((application, Some(addresses)));
    data.certificate_duration_days = VALID_DAYS;
    store
        .create_and_store_application_instance_cert(&data, true)
        .map_err(|e| format!("--opcua: cannot create the server certificate in {}: {e}", dir.display()))?;
    tracing::info!(pki = %dir.display(), "OPC UA server certificate created");
    Ok(())
}

#[cfg(unix)]
fn create_private_dir(dir: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::DirBuilderExt;
    std::fs::DirBuilder::new().recursive(true).mode(0o700).create(dir)
}

#[cfg(not(unix))]
fn create_private_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beside_a_file_or_temporary() {
        let pki = Pki::beside(Some(Path::new("/data/fivex.db")));
        assert_eq!(pki.dir, Path::new("/data/fivex.db-opcua-pki"));
        assert!(!pki.temporary);
        let a = Pki::beside(None);
        let b = Pki::beside(None);
        assert!(a.temporary && a.dir.starts_with(std::env::temp_dir()));
        assert_ne!(a.dir, b.dir, "one per process start");
    }
}
