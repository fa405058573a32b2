//! The NC parser must accept any bytes without panicking (docs/contracts.md: bad input never panics).
#![no_main]

use fivex_engine::Dialect;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The CLI reads files the same way: lossy UTF-8.
    let text = String::from_utf8_lossy(data);
    let file = fivex_engine::lang::parse_file(&text);
    for d in &file.diagnostics {
        assert!(d.line >= 1, "diagnostic lines are 1-based: {d:?}");
    }
    // The static checks walk the same tree: exercise them too.
    for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
        let _ = fivex_engine::check::check(file.clone(), dialect);
    }
});
