//! Lines → blocks → programs. Every block is parsed on its own, so one bad block yields one
//! diagnostic and parsing goes on with the next.

use super::ast::*;
use super::diag::Diagnostic;
use super::lexer::{Kw, Lexer, Tok};
use crate::alarm::AlarmId;

/// Brackets may nest this deep (FANUC: five levels, function brackets included).
const MAX_BRACKET_DEPTH: u32 = 5;

/// Most digits a number written at an address may have, in least input increments
/// (`lexer::increment_digits`; more: PS0003 TOO MANY DIGITS): FANUC's nine digits of the least
/// input increment (IS-B ±999999.999, the 5-axis manual's data ranges); a sequence number has
/// eight (N1–N99999999). `docs/dialects.md`, "Too many digits".
const MAX_DIGITS: usize = 9;

/// Parse a whole NC file. Never fails: problems are collected in `File::diagnostics` and the
/// offending blocks become [`BlockKind::Error`].
pub fn parse_file(text: &str) -> File {
    parse_part(text, 1, false)
}

/// Parse the lines of a file from line `first_line` on. A part that `continues` an earlier one
/// starts inside that part's last program: its leading blocks form an anonymous program that
/// belongs there (`Interpreter::push_part` puts it back), and no header rule applies.
pub fn parse_part(text: &str, first_line: u32, continues: bool) -> File {
    let mut file = File::default();
    let mut current: Option<Program> = None;
    // Most files are one program: size its block list once (NC lines are rarely shorter than
    // 16 bytes) instead of growing it.
    let mut reserve = text.len() / 16 + 16;
    let mut new_program = |number: Option<u32>, line: u32| {
        let blocks = Vec::with_capacity(std::mem::take(&mut reserve));
        Program { number, line, blocks }
    };
    let across = block_comments_across_lines(text);
    for (idx, line) in lines(text).enumerate() {
        let line_no = first_line + idx as u32;
        file.lines = idx as u32 + 1;
        let trimmed = trim_start(line);
        if trimmed.is_empty() {
            continue;
        }
        if trimmed.starts_with('%') {
            // `%` lines delimit the file and are ignored, but for Syntec's `%@MACRO`.
            if let Some(block) = macro_format(trimmed, line_no, (line.len() - trimmed.len()) as u32 + 1) {
                current.get_or_insert_with(|| new_program(None, line_no)).blocks.push(block);
            }
            continue;
        }
        let mut block_comment = unclosed_block_comment(line)
            .or_else(|| across.iter().find(|&&(i, _)| i == idx).map(|&(_, at)| at))
            .map(|at| block_comment_refusal(line_no, at as u32 + 1));
        // A `;` ends a block; text after it on the same line is another block.
        let mut start = 0usize;
        while start < line.len() {
            let segment = &line[start..];
            let mut col0 = start as u32 + 1;
            let mut rest = segment;
            if let Some((number, after)) = program_number(segment) {
                let mut carried = Vec::new();
                if let Some(p) = current.take() {
                    // Comments before the first O number are a file header, not a program; the
                    // Syntec dialect's refusals among them go on to the program.
                    if continues || !is_header(&p) {
                        file.programs.push(p);
                    } else {
                        carried = p.blocks.into_iter().filter(|b| matches!(b.kind, BlockKind::SyntecOnly(_))).collect();
                    }
                }
                let mut program = new_program(Some(number), line_no);
                program.blocks.extend(carried);
                current = Some(program);
                rest = &segment[after..];
                col0 += after as u32;
            }
            // The whole line lies in Syntec's block comment: its refusal comes before its blocks.
            if let Some(block) = block_comment.take() {
                current.get_or_insert_with(|| new_program(None, line_no)).blocks.push(block);
            }
            let (block, next) = parse_block(rest, col0, line_no);
            if !is_blank(&block) {
                if let BlockKind::Error(d) = &block.kind {
                    file.diagnostics.push(d.clone());
                }
                current.get_or_insert_with(|| new_program(None, line_no)).blocks.push(block);
            }
            match next {
                Some(n) => start = col0 as usize - 1 + n,
                None => break,
            }
        }
    }
    if let Some(p) = current.take() {
        file.programs.push(p);
    }
    file
}

/// Comments before the first O number are a file header, not a program.
pub fn is_header(p: &Program) -> bool {
    p.number.is_none() && p.blocks.iter().all(is_header_block)
}

/// A block a file header may hold: comments only (Syntec's `%@MACRO` and block comments are
/// nothing in the other dialects).
pub fn is_header_block(b: &Block) -> bool {
    let nothing = match &b.kind {
        BlockKind::Empty => true,
        BlockKind::SyntecOnly(s) => s.others.is_none(),
        _ => false,
    };
    nothing && b.n.is_none()
}

/// A block the Syntec dialect refuses as not built at `line`, `col`, and the others read as
/// nothing.
fn syntec_only(line: u32, col: u32, detail: &str, whole_file: bool) -> Block {
    let syntec = Diagnostic { line, col, id: AlarmId::AddressNotBuilt, detail: detail.into() };
    let kind = BlockKind::SyntecOnly(Box::new(SyntecOnly { syntec, others: None, whole_file }));
    Block { line, col, block_delete: None, n: None, kind, comment: None }
}

/// Syntec's `%@MACRO` line (the Syntec MACRO syntax handbook, §1.1: a file whose first line it
/// is runs in the MACRO format): fivex runs FANUC's custom macro B, whose text a MACRO-format
/// file shares with other meanings (variable numbers, integer division, comments), so the
/// Syntec dialect refuses the file, before anything of it runs, wherever the line stands
/// (`docs/dialects.md`, "The Syntec macro language").
fn macro_format(trimmed: &str, line: u32, col: u32) -> Option<Block> {
    is_macro_format(trimmed)
        .then(|| syntec_only(line, col, "the Syntec MACRO-format file (%@MACRO) is not built in fivex", true))
}

fn is_macro_format(trimmed: &str) -> bool {
    trimmed.as_bytes().get(..7).is_some_and(|h| h.eq_ignore_ascii_case(b"%@MACRO"))
}

/// Whether `text` holds a Syntec `%@MACRO` line: a reader that hands a file over in parts gives
/// such a file as one part, so the Syntec dialect can refuse it before anything of it runs.
pub fn has_macro_format_line(text: &str) -> bool {
    lines(text).any(|l| is_macro_format(trim_start(l)))
}

/// The block the Syntec dialect refuses at a `(*` that nothing closes on its line.
fn block_comment_refusal(line: u32, col: u32) -> Block {
    syntec_only(line, col, "the Syntec block comment (* … *) across lines is not built in fivex", false)
}

/// Where a comment that opens `(*` runs on past its line's end (the byte offset of the `(`).
/// Every file the Syntec dialect runs is an ISO-format file (a MACRO-format file, `%@MACRO`, is
/// refused whole), where a comment is `( … )` (handbook §4.10), so `(* ROUGH)` and
/// `(*** TOOL 1 ***)`, as posts write them, are comments to their `)`. Only a `(*` with no `)`
/// after it on the line is refused: it was written as a MACRO-format block comment across lines
/// (§4.10), and its lines would run in an ISO-format file as in fivex, not as the writer meant.
fn unclosed_block_comment(line: &str) -> Option<usize> {
    let b = line.as_bytes();
    let mut i = 0;
    while let Some(k) = memchr::memchr(b'(', &b[i..]) {
        let open = i + k;
        match memchr::memchr(b')', &b[open + 1..]) {
            Some(c) => i = open + 1 + c + 1,
            None if b.get(open + 1) == Some(&b'*') => return Some(open),
            // An ordinary comment unclosed runs to the end of the line.
            None => return None,
        }
    }
    None
}

/// The lines (index in `text`, offset of the `(`) that open a Syntec block comment a later line
/// closes: a `(*` that no `*)` after it on its line closes, and a later line with a `*)` that
/// no `(*` before it on that line opens. Read as ISO comments, `(* old roughing (T1)` ends at
/// its `)` and the lines up to `end *)` would run, where the writer meant them commented out
/// (handbook §4.10), so its line is refused as `unclosed_block_comment`'s is.
fn block_comments_across_lines(text: &str) -> Vec<(usize, usize)> {
    use memchr::memmem::find;
    let mut found = Vec::new();
    if find(text.as_bytes(), b"(*").is_none() {
        return found;
    }
    let mut open = None;
    for (idx, line) in lines(text).enumerate() {
        let b = line.as_bytes();
        let closes = find(b, b"*)").is_some_and(|end| find(&b[..end + 1], b"(*").is_none());
        if closes {
            found.extend(open.take());
        }
        let mut from = 0;
        while let Some(k) = find(&b[from..], b"(*") {
            let at = from + k;
            if find(&b[at + 2..], b"*)").is_none() {
                // The first opener since the last close: refused there, before any line the
                // writer meant commented out can run.
                open.get_or_insert((idx, at));
                break;
            }
            from = at + 2;
        }
    }
    found
}

/// A block with nothing in it at all (not even a comment) is not a block.
fn is_blank(b: &Block) -> bool {
    b.kind == BlockKind::Empty && b.n.is_none() && b.block_delete.is_none() && b.comment.is_none()
}

/// The lines of `text` as `str::lines` cuts them (at `\n`, without a `\r` before it), with a
/// vectorised search for the line ends: this runs for every line of every program.
fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = text;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let line = match memchr::memchr(b'\n', rest.as_bytes()) {
            Some(i) => {
                let line = &rest[..i];
                rest = &rest[i + 1..];
                line.strip_suffix('\r').unwrap_or(line)
            }
            None => std::mem::take(&mut rest),
        };
        Some(line)
    })
}

/// `str::trim_start`, without its Unicode decoding for the common line that starts with an
/// ASCII letter or digit.
fn trim_start(s: &str) -> &str {
    match s.as_bytes().first() {
        Some(b) if b.is_ascii_alphanumeric() => s,
        _ => s.trim_start(),
    }
}

/// `O1234` (or `:1234`, the ISO code form FANUC reads as O) at the start of a segment: the
/// number and the byte offset after it.
fn program_number(segment: &str) -> Option<(u32, usize)> {
    let lead = segment.len() - trim_start(segment).len();
    let bytes = segment.as_bytes();
    if !matches!(bytes.get(lead), Some(b'O') | Some(b'o') | Some(b':')) {
        return None;
    }
    let digits = bytes[lead + 1..].iter().take_while(|b| b.is_ascii_digit()).count();
    if digits == 0 || digits > 8 {
        return None;
    }
    let end = lead + 1 + digits;
    let number = segment[lead + 1..end].parse::<u32>().ok()?;
    Some((number, end))
}

/// Operators and functions one block may hold. A real control bounds a block's length; this
/// bound keeps evaluation and dropping of the tree shallow whatever the input.
const MAX_EXPR_NODES: u32 = 500;

struct BlockParser<'a> {
    lx: Lexer<'a>,
    line: u32,
    depth: u32,
    /// Operators and functions parsed so far in this block.
    nodes: u32,
}

type PResult<T> = Result<T, Diagnostic>;

/// Parse one block from the start of `text`; also returns where the next block of the line
/// starts (after a `;`), relative to `text`.
fn parse_block(text: &str, col0: u32, line: u32) -> (Block, Option<usize>) {
    if let Some(block) = plain_words(text.as_bytes(), col0, line) {
        return (block, None);
    }
    let mut p = BlockParser { lx: Lexer::new(text.as_bytes(), col0), line, depth: 0, nodes: 0 };
    let col = col0 + (text.len() - text.trim_start().len()) as u32;
    let mut block = Block { line, col, block_delete: None, n: None, kind: BlockKind::Empty, comment: None };
    match p.block(&mut block) {
        Ok(kind) => block.kind = kind,
        Err(d) => {
            block.kind = match syntec_structure(text) {
                Some(name) => {
                    let detail = format!("the Syntec statement {name} (MACRO-format structure) is not built in fivex");
                    let syntec = Diagnostic { line, col, id: AlarmId::AddressNotBuilt, detail };
                    BlockKind::SyntecOnly(Box::new(SyntecOnly { syntec, others: Some(d), whole_file: true }))
                }
                None => BlockKind::Error(d),
            }
        }
    }
    // After an error the rest of the block is skipped, up to a `;` outside comments.
    let next = match p.lx.after_semicolon() {
        Some(n) => Some(n),
        None => p.lx.skip_to_semicolon(),
    };
    block.comment = p.lx.first_comment();
    (block, next)
}

/// The Syntec MACRO-format structured statement a block that FANUC text cannot read starts with
/// (handbook §4.1: the ends of `IF … THEN … END_IF` and `WHILE … DO … END_WHILE`, `FOR`,
/// `REPEAT … UNTIL`, `CASE … OF`, `ELSE`, `ELSEIF`, and the `ENDIF`… forms). Its blocks before and after belong to
/// a structure fivex does not build: a branch not taken ran its moves before the refusal at
/// `END_IF`. So the Syntec dialect refuses the whole file there, before anything of it runs, as it
/// refuses `%@MACRO`; FANUC and Haas keep their own error for the block.
fn syntec_structure(text: &str) -> Option<&'static str> {
    // Not `IF` and `WHILE`: FANUC's own statements, whose errors (a bracket too deep) stay
    // theirs; a Syntec block IF or WHILE is refused at its `END_IF` / `END_WHILE`.
    const NAMES: [&str; 16] = [
        "FOR",
        "REPEAT",
        "UNTIL",
        "CASE",
        "ELSE",
        "ELSEIF",
        "END_IF",
        "ENDIF",
        "END_WHILE",
        "ENDWHILE",
        "END_FOR",
        "ENDFOR",
        "END_REPEAT",
        "ENDREPEAT",
        "END_CASE",
        "ENDCASE",
    ];
    let t = text.trim_start();
    let len = t.bytes().position(|c| !(c.is_ascii_alphabetic() || c == b'_')).unwrap_or(t.len());
    let word = &t[..len];
    NAMES.iter().copied().find(|n| word.eq_ignore_ascii_case(n))
}

/// The fast path for the common block: `[N…] Letter Number …` with nothing else (no macro
/// syntax, comments, `;` or `/`). Returns `None` for anything else, which the general parser then
/// reads; both give the same block (`plain_words_agrees_with_the_general_parser`).
fn plain_words(t: &[u8], col0: u32, line: u32) -> Option<Block> {
    let blank = |c: u8| c == b' ' || c == b'\t' || c == b'\r';
    let mut i = 0;
    while i < t.len() && blank(t[i]) {
        i += 1;
    }
    let col = col0 + i as u32;
    let mut words = Words::new();
    let mut n = None;
    while i < t.len() {
        let letter = t[i].to_ascii_uppercase();
        if !letter.is_ascii_uppercase() || t.get(i + 1).is_some_and(|c| c.is_ascii_alphabetic()) {
            return None;
        }
        let letter_col = col0 + i as u32;
        i += 1;
        while i < t.len() && blank(t[i]) {
            i += 1;
        }
        let signed = matches!(t.get(i), Some(b'-' | b'+'));
        let negative = match t.get(i) {
            Some(b'-') => true,
            Some(b'+') => false,
            Some(b'0'..=b'9' | b'.') => {
                i -= 1;
                false
            }
            _ => return None,
        };
        i += 1;
        if !t.get(i).is_some_and(|c| c.is_ascii_digit() || *c == b'.') {
            return None;
        }
        let (Tok::Num { value, point }, end) = super::lexer::number_at(t, i) else { return None };
        if super::lexer::increment_digits(&t[i..]) > MAX_DIGITS {
            return None;
        }
        i = end;
        if letter == b'N' && words.is_empty() && n.is_none() {
            if signed || point || value > 99_999_999.0 {
                return None;
            }
            n = Some(value as u32);
        } else {
            let value = if negative { -value } else { value };
            words.push(Word { letter, value: WordValue::Number { value, decimal_point: point }, col: letter_col });
        }
        while i < t.len() && blank(t[i]) {
            i += 1;
        }
    }
    if words.is_empty() {
        return None;
    }
    Some(Block { line, col, block_delete: None, n, kind: BlockKind::Words(words), comment: None })
}

impl BlockParser<'_> {
    fn err<T>(&self, col: u32, id: AlarmId, detail: impl Into<String>) -> PResult<T> {
        Err(Diagnostic { line: self.line, col, id, detail: detail.into() })
    }

    fn block(&mut self, block: &mut Block) -> PResult<BlockKind> {
        if let (Tok::Slash, _) = self.lx.peek() {
            self.lx.next_tok();
            let level = match self.lx.peek() {
                (Tok::Num { value, point: false }, _) if (1.0..=9.0).contains(&value) => {
                    self.lx.next_tok();
                    value as u8
                }
                _ => 1,
            };
            block.block_delete = Some(level);
        }
        if let (Tok::Letter(b'N'), col) = self.lx.peek() {
            self.lx.next_tok();
            match self.lx.next_tok() {
                (Tok::Num { value, point: false }, _) if value <= 99_999_999.0 => block.n = Some(value as u32),
                (Tok::Num { point: false, .. }, c) => {
                    return self.err(c, AlarmId::TooManyDigits, "a sequence number has at most 8 digits")
                }
                (_, c) => {
                    return self.err(c.max(col), AlarmId::NoDataAfterAddress, "N needs an integer sequence number")
                }
            }
        }
        let (tok, col) = self.lx.peek();
        let kind = match tok {
            Tok::Eof => return Ok(BlockKind::Empty),
            Tok::Hash => {
                self.lx.next_tok();
                let var = self.variable_after_hash(col)?;
                self.expect(Tok::Assign, "expected '=' after the variable")?;
                let value = self.expr(false)?;
                BlockKind::Assign { var, value }
            }
            Tok::Kw(Kw::If) => {
                self.lx.next_tok();
                let cond = self.condition()?;
                match self.lx.next_tok() {
                    (Tok::Kw(Kw::Goto), _) => BlockKind::IfGoto { cond, target: self.expr(false)? },
                    (Tok::Kw(Kw::Then), _) => {
                        let (t, c) = self.lx.next_tok();
                        if t != Tok::Hash {
                            return self.err(
                                c,
                                AlarmId::MacroFormat,
                                "THEN must be followed by an assignment '#i = …'",
                            );
                        }
                        let var = self.variable_after_hash(c)?;
                        self.expect(Tok::Assign, "expected '=' after the variable")?;
                        let value = self.expr(false)?;
                        BlockKind::IfThen { cond, var, value }
                    }
                    (_, c) => {
                        return self.err(c, AlarmId::MacroFormat, "IF [condition] must be followed by GOTO or THEN")
                    }
                }
            }
            Tok::Kw(Kw::Goto) => {
                self.lx.next_tok();
                BlockKind::Goto(self.expr(false)?)
            }
            Tok::Kw(Kw::While) => {
                self.lx.next_tok();
                let cond = self.condition()?;
                match self.lx.next_tok() {
                    (Tok::Kw(Kw::Do), _) => BlockKind::Do { cond: Some(cond), id: self.loop_id()? },
                    (_, c) => return self.err(c, AlarmId::MacroFormat, "WHILE [condition] must be followed by DO m"),
                }
            }
            Tok::Kw(Kw::Do) => {
                self.lx.next_tok();
                BlockKind::Do { cond: None, id: self.loop_id()? }
            }
            Tok::Kw(Kw::End) => {
                self.lx.next_tok();
                BlockKind::End { id: self.loop_id()? }
            }
            Tok::Kw(Kw::Popen) => {
                self.lx.next_tok();
                BlockKind::Output(Output::Open)
            }
            Tok::Kw(Kw::Pclos) => {
                self.lx.next_tok();
                BlockKind::Output(Output::Close)
            }
            Tok::Kw(Kw::Dprnt) => {
                self.lx.next_tok();
                BlockKind::Output(Output::Print(self.print_items(false)?))
            }
            Tok::Kw(Kw::Bprnt) => {
                self.lx.next_tok();
                BlockKind::Output(Output::BinaryPrint(self.print_items(true)?))
            }
            Tok::Letter(_) => match self.lx.syntec_statement_at(col) {
                Some(name) => return Ok(self.syntec_statement(name, col)),
                None => BlockKind::Words(self.words()?),
            },
            // `[cond] M99 P<n>` (Haas NGC): read in every dialect, refused where it is none.
            Tok::LBracket => {
                let cond = self.condition()?;
                match self.lx.peek() {
                    (Tok::Letter(_), _) => BlockKind::IfWords { cond, words: self.words()? },
                    (tok, col) => return self.unexpected(tok, col),
                }
            }
            _ => return self.unexpected(tok, col),
        };
        match self.lx.peek() {
            (Tok::Eof, _) => Ok(kind),
            (Tok::Hash, col) => self.err(col, AlarmId::MixedStatements, "a macro statement and NC words in one block"),
            (Tok::Letter(_), col) if !matches!(kind, BlockKind::Words(_)) => {
                self.err(col, AlarmId::MixedStatements, "a macro statement and NC words in one block")
            }
            (tok, col) => self.unexpected(tok, col),
        }
    }

    /// A Syntec statement (`ALARM(…)`, `MSG(…)`, `SLEEP(…)`, `WAIT(…)`, `EXIT`): refused by name
    /// as not built in the Syntec dialect; the others keep what they read, an address without
    /// a value (`ALARM` is the address A, then L: a name's second letter is never a value).
    fn syntec_statement(&mut self, name: &str, col: u32) -> BlockKind {
        let detail = format!("the Syntec statement {name} is not built in fivex");
        let syntec = Diagnostic { line: self.line, col, id: AlarmId::AddressNotBuilt, detail };
        let others = self.words().err();
        BlockKind::SyntecOnly(Box::new(SyntecOnly { syntec, others, whole_file: false }))
    }

    fn unexpected<T>(&self, tok: Tok, col: u32) -> PResult<T> {
        match tok {
            // Syntec's `@` variables (`@980 = TIME[3]`, written by Autodesk's SYIL post).
            Tok::Bad(b'@') => {
                self.err(col, AlarmId::AddressNotBuilt, "the @ variables (Syntec) are not built in fivex")
            }
            Tok::Bad(c) => self.err(col, AlarmId::Syntax, format!("unexpected character '{}'", c as char)),
            Tok::BadNumber => self.err(col, AlarmId::Syntax, "more than one decimal point in a number"),
            Tok::TooManyDigits => self.err(col, AlarmId::TooManyDigits, "more than 15 digits in a number"),
            Tok::Assign => self.err(col, AlarmId::MixedStatements, "an assignment after NC words"),
            Tok::Kw(_) => self.err(col, AlarmId::MacroFormat, "a macro keyword out of place"),
            Tok::Eof => self.err(col, AlarmId::MacroFormat, "unexpected end of block"),
            other => self.err(col, AlarmId::Syntax, format!("unexpected {}", describe(other))),
        }
    }

    fn expect(&mut self, want: Tok, detail: &str) -> PResult<()> {
        let (tok, col) = self.lx.next_tok();
        if tok == want {
            Ok(())
        } else {
            self.err(col, AlarmId::MacroFormat, detail)
        }
    }

    fn loop_id(&mut self) -> PResult<u8> {
        match self.lx.next_tok() {
            (Tok::Num { value, point: false }, _) if value <= 255.0 => Ok(value as u8),
            (_, col) => self.err(col, AlarmId::IllegalLoopNumber, "DO/END need a loop number 1, 2 or 3"),
        }
    }

    fn words(&mut self) -> PResult<Words> {
        let mut words = Words::new();
        // After `,L` only I, J, K may come, and they belong to it (FANUC §2.2.4).
        let mut after_l = false;
        loop {
            let (letter, col) = match self.lx.peek() {
                (Tok::Letter(letter), col) => {
                    self.lx.next_tok();
                    if after_l && !matches!(letter, b'I' | b'J' | b'K') {
                        return self.err(col, AlarmId::ImproperAddress, "only I, J, K may follow ,L");
                    }
                    (if after_l { letter.to_ascii_lowercase() } else { letter }, col)
                }
                (Tok::Comma, col) => {
                    self.lx.next_tok();
                    match self.lx.next_tok() {
                        (Tok::Letter(letter @ (b'A' | b'C' | b'L' | b'R')), _) if !after_l => {
                            after_l = letter == b'L';
                            (letter.to_ascii_lowercase(), col)
                        }
                        _ => return self.err(col, AlarmId::Syntax, "a comma address is ,A ,C ,R or ,L"),
                    }
                }
                _ => break,
            };
            let value = self.word_value(letter.to_ascii_uppercase(), col)?;
            words.push(Word { letter, value, col });
        }
        Ok(words)
    }

    fn word_value(&mut self, letter: u8, letter_col: u32) -> PResult<WordValue> {
        let (tok, col) = self.lx.next_tok();
        let (negative, tok, col) = match tok {
            Tok::Minus => {
                let (t, c) = self.lx.next_tok();
                (true, t, c)
            }
            Tok::Plus => {
                let (t, c) = self.lx.next_tok();
                (false, t, c)
            }
            _ => (false, tok, col),
        };
        let sign = |e: Expr| if negative { Expr::Neg(Box::new(e)) } else { e };
        match tok {
            Tok::Num { .. } if self.lx.digits_at(col) > MAX_DIGITS => {
                self.err(col, AlarmId::TooManyDigits, format!("{} has at most {MAX_DIGITS} digits", letter as char))
            }
            Tok::Num { value, point } => {
                Ok(WordValue::Number { value: if negative { -value } else { value }, decimal_point: point })
            }
            Tok::Hash => Ok(WordValue::Expr(Box::new(sign(self.variable_after_hash(col)?)))),
            Tok::LBracket => {
                let inner = self.bracketed(col, false)?;
                Ok(WordValue::Expr(Box::new(sign(Expr::Bracket(Box::new(inner))))))
            }
            Tok::BadNumber | Tok::TooManyDigits => self.unexpected(tok, col),
            _ => self.err(letter_col, AlarmId::NoDataAfterAddress, format!("address {} has no value", letter as char)),
        }
    }

    /// After `#`: a number or a bracketed expression.
    fn variable_after_hash(&mut self, hash_col: u32) -> PResult<Expr> {
        match self.lx.next_tok() {
            (Tok::Num { value, point: false }, _) if value <= u32::MAX as f64 => Ok(Expr::Var(value as u32)),
            (Tok::LBracket, col) => Ok(Expr::IndirectVar(Box::new(self.bracketed(col, false)?))),
            _ => self.err(hash_col, AlarmId::MacroFormat, "'#' must be followed by a variable number or [expression]"),
        }
    }

    /// After `[`: the expression and its closing `]`.
    fn bracketed(&mut self, open_col: u32, allow_cmp: bool) -> PResult<Expr> {
        self.depth += 1;
        if self.depth > MAX_BRACKET_DEPTH {
            return self.err(open_col, AlarmId::BracketNesting, "brackets nest deeper than 5 levels");
        }
        let e = self.expr(allow_cmp)?;
        match self.lx.next_tok() {
            (Tok::RBracket, _) => {
                self.depth -= 1;
                Ok(e)
            }
            (_, col) => self.err(col, AlarmId::MacroFormat, "missing ']'"),
        }
    }

    fn condition(&mut self) -> PResult<Expr> {
        match self.lx.next_tok() {
            (Tok::LBracket, col) => self.bracketed(col, true),
            (_, col) => self.err(col, AlarmId::MacroFormat, "a condition must be in brackets: [ … ]"),
        }
    }

    fn expr(&mut self, allow_cmp: bool) -> PResult<Expr> {
        self.binary(if allow_cmp { 1 } else { 2 }, allow_cmp)
    }

    /// Count one operator or function against the block's budget.
    fn node(&mut self, col: u32) -> PResult<()> {
        self.nodes += 1;
        if self.nodes > MAX_EXPR_NODES {
            return self.err(col, AlarmId::MacroFormat, format!("more than {MAX_EXPR_NODES} operators in one block"));
        }
        Ok(())
    }

    fn binary(&mut self, min_prec: u8, allow_cmp: bool) -> PResult<Expr> {
        let mut lhs = self.unary(allow_cmp)?;
        loop {
            let Some(op) = binop(self.lx.peek().0) else { return Ok(lhs) };
            if op.precedence() < min_prec {
                return Ok(lhs);
            }
            let col = self.lx.col();
            self.node(col)?;
            self.lx.next_tok();
            let rhs = self.binary(op.precedence() + 1, allow_cmp)?;
            lhs = Expr::Binary(op, Box::new(lhs), Box::new(rhs));
        }
    }

    fn unary(&mut self, allow_cmp: bool) -> PResult<Expr> {
        match self.lx.peek() {
            (Tok::Minus, col) => {
                self.node(col)?;
                self.lx.next_tok();
                Ok(Expr::Neg(Box::new(self.unary(allow_cmp)?)))
            }
            (Tok::Plus, col) => {
                self.node(col)?;
                self.lx.next_tok();
                self.unary(allow_cmp)
            }
            _ => self.primary(allow_cmp),
        }
    }

    fn primary(&mut self, allow_cmp: bool) -> PResult<Expr> {
        let (tok, col) = self.lx.next_tok();
        match tok {
            Tok::Num { value, point } => Ok(Expr::Num { value, decimal_point: point }),
            Tok::Hash => self.variable_after_hash(col),
            Tok::LBracket => Ok(Expr::Bracket(Box::new(self.bracketed(col, allow_cmp)?))),
            Tok::Kw(Kw::Func(f)) => {
                self.node(col)?;
                let arg = self.func_arg()?;
                Ok(Expr::Func(f, Box::new(arg)))
            }
            Tok::Kw(Kw::Atan) => {
                self.node(col)?;
                let open = self.lx.col();
                self.expect(Tok::LBracket, "ATAN needs '['")?;
                let a = self.expr(false)?;
                match self.lx.next_tok() {
                    (Tok::Comma, _) => {
                        let b = self.expr(false)?;
                        self.close_func(open)?;
                        Ok(Expr::Func2(Func2::Atan, Box::new(a), Box::new(b)))
                    }
                    (Tok::RBracket, _) => {
                        self.check_depth(open)?;
                        // `ATAN[a]/[b]` is the two-argument form.
                        let (t1, _) = self.lx.peek();
                        if t1 == Tok::Slash {
                            self.lx.next_tok();
                            let (t2, c2) = self.lx.next_tok();
                            if t2 != Tok::LBracket {
                                return self.err(c2, AlarmId::MacroFormat, "ATAN[a]/ must be followed by [b]");
                            }
                            let b = self.bracketed(c2, false)?;
                            Ok(Expr::Func2(Func2::Atan, Box::new(a), Box::new(b)))
                        } else {
                            Ok(Expr::Func(Func::Atan, Box::new(a)))
                        }
                    }
                    (_, c) => self.err(c, AlarmId::MacroFormat, "missing ']'"),
                }
            }
            Tok::Kw(Kw::Pow) => {
                self.node(col)?;
                let open = self.lx.col();
                self.expect(Tok::LBracket, "POW needs '['")?;
                let a = self.expr(false)?;
                self.expect(Tok::Comma, "POW needs two arguments: POW[a,b]")?;
                let b = self.expr(false)?;
                self.close_func(open)?;
                Ok(Expr::Func2(Func2::Pow, Box::new(a), Box::new(b)))
            }
            Tok::Eof => self.err(col, AlarmId::MacroFormat, "expression expected"),
            Tok::Letter(_) => match self.lx.function_name_at(col) {
                // Another control's function (FANUC's PRM[] parameter read, Syntec's R_…[] and
                // TIME[]): named as not built rather than a stray address
                // (`docs/dialects.md`, "Functions not built").
                Some(name) => {
                    self.err(col, AlarmId::AddressNotBuilt, format!("the function {name}[] is not built in fivex"))
                }
                None => self.unexpected(tok, col),
            },
            other => self.unexpected(other, col),
        }
    }

    /// `[expr]` after a function name; the function's brackets count towards the nesting limit.
    fn func_arg(&mut self) -> PResult<Expr> {
        match self.lx.next_tok() {
            (Tok::LBracket, col) => self.bracketed(col, false),
            (_, col) => self.err(col, AlarmId::MacroFormat, "a function's argument must be in brackets"),
        }
    }

    fn check_depth(&self, open_col: u32) -> PResult<()> {
        if self.depth + 1 > MAX_BRACKET_DEPTH {
            return self.err(open_col, AlarmId::BracketNesting, "brackets nest deeper than 5 levels");
        }
        Ok(())
    }

    fn close_func(&mut self, open_col: u32) -> PResult<()> {
        self.check_depth(open_col)?;
        self.expect(Tok::RBracket, "missing ']'")
    }

    /// DPRNT/BPRNT: `[text #var[ab] text …]`. Text is raw: letters, digits and signs print as
    /// written, `*` prints a space, spaces are not printed. A DPRNT variable's format is
    /// `[ab]` (a integer and b decimal digits); a BPRNT variable's is `[c]`, its c decimal
    /// places (the value goes out as a 32-bit integer of that many decimals).
    fn print_items(&mut self, binary: bool) -> PResult<Vec<PrintItem>> {
        let start_col = self.lx.col();
        let raw = self.lx.rest();
        if raw.first() != Some(&b'[') {
            return self.err(start_col, AlarmId::MacroFormat, "DPRNT needs [ … ]");
        }
        let mut items = Vec::new();
        let mut text = String::new();
        let mut i = 1;
        while i < raw.len() {
            match raw[i] {
                b']' => {
                    if !text.is_empty() {
                        items.push(PrintItem::Text(std::mem::take(&mut text)));
                    }
                    self.lx.advance_raw(i + 1);
                    return Ok(items);
                }
                b'#' => {
                    if !text.is_empty() {
                        items.push(PrintItem::Text(std::mem::take(&mut text)));
                    }
                    let digits = raw[i + 1..].iter().take_while(|b| b.is_ascii_digit()).count();
                    if digits == 0 {
                        return self.err(
                            start_col + i as u32,
                            AlarmId::MacroFormat,
                            "DPRNT variables are written #number[ab]",
                        );
                    }
                    let number: u32 = std::str::from_utf8(&raw[i + 1..i + 1 + digits])
                        .ok()
                        .and_then(|s| s.parse().ok())
                        .unwrap_or(u32::MAX);
                    i += 1 + digits;
                    let (mut int_digits, mut frac_digits) = (8u8, 0u8);
                    if binary {
                        if raw.get(i) == Some(&b'[') && raw.get(i + 2) == Some(&b']') && raw[i + 1].is_ascii_digit() {
                            frac_digits = raw[i + 1] - b'0';
                            i += 3;
                        }
                    } else if raw.get(i) == Some(&b'[')
                        && raw.get(i + 3) == Some(&b']')
                        && raw[i + 1].is_ascii_digit()
                        && raw[i + 2].is_ascii_digit()
                    {
                        int_digits = raw[i + 1] - b'0';
                        frac_digits = raw[i + 2] - b'0';
                        i += 4;
                    }
                    items.push(PrintItem::Var { var: Expr::Var(number), int_digits, frac_digits });
                }
                b'*' => {
                    text.push(' ');
                    i += 1;
                }
                b' ' | b'\t' => i += 1,
                c => {
                    text.push(c.to_ascii_uppercase() as char);
                    i += 1;
                }
            }
        }
        self.err(start_col, AlarmId::MacroFormat, "DPRNT is missing its closing ']'")
    }
}

fn binop(tok: Tok) -> Option<BinOp> {
    Some(match tok {
        Tok::Star => BinOp::Mul,
        Tok::Slash => BinOp::Div,
        Tok::Plus => BinOp::Add,
        Tok::Minus => BinOp::Sub,
        Tok::Kw(Kw::And) => BinOp::And,
        Tok::Kw(Kw::Mod) => BinOp::Mod,
        Tok::Kw(Kw::Or) => BinOp::Or,
        Tok::Kw(Kw::Xor) => BinOp::Xor,
        Tok::Kw(Kw::Eq) => BinOp::Eq,
        Tok::Kw(Kw::Ne) => BinOp::Ne,
        Tok::Kw(Kw::Gt) => BinOp::Gt,
        Tok::Kw(Kw::Ge) => BinOp::Ge,
        Tok::Kw(Kw::Lt) => BinOp::Lt,
        Tok::Kw(Kw::Le) => BinOp::Le,
        _ => return None,
    })
}

fn describe(tok: Tok) -> String {
    match tok {
        Tok::Letter(c) => format!("address {}", c as char),
        Tok::Num { value, .. } => format!("number {value}"),
        Tok::Hash => "'#'".into(),
        Tok::LBracket => "'['".into(),
        Tok::RBracket => "']'".into(),
        Tok::Comma => "','".into(),
        Tok::Assign => "'='".into(),
        Tok::Plus => "'+'".into(),
        Tok::Minus => "'-'".into(),
        Tok::Star => "'*'".into(),
        Tok::Slash => "'/'".into(),
        Tok::Kw(k) => format!("keyword {k:?}"),
        Tok::Bad(c) => format!("character '{}'", c as char),
        Tok::BadNumber | Tok::TooManyDigits => "malformed number".into(),
        Tok::Eof => "end of block".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn general(text: &str) -> Block {
        let mut p = BlockParser { lx: Lexer::new(text.as_bytes(), 1), line: 1, depth: 0, nodes: 0 };
        let col = 1 + (text.len() - text.trim_start().len()) as u32;
        let mut block = Block { line: 1, col, block_delete: None, n: None, kind: BlockKind::Empty, comment: None };
        block.kind = match p.block(&mut block) {
            Ok(kind) => kind,
            Err(d) => BlockKind::Error(d),
        };
        block
    }

    #[test]
    fn plain_words_examples() {
        for text in ["G01 X12.345 Y-3.21 Z-0.5", "N10 G0 X1", "n5 g1 x.5 y-.5", "X 1", "G43.4 H1", "N1 N2"] {
            assert_eq!(plain_words(text.as_bytes(), 1, 1).as_ref(), Some(&general(text)), "{text}");
        }
        for text in ["#1=2", "X[1]", "X#1", "GOTO1", "N1.5 X1", "X1 (c)", "/X1", "X1;Y2", "N-1 X1", "X", "X- 1"] {
            assert!(plain_words(text.as_bytes(), 1, 1).is_none(), "{text}");
        }
    }

    proptest! {
        /// The line cutter and the trimmer are `str::lines` and `str::trim_start`.
        #[test]
        fn lines_and_trim_are_the_standard_ones(text in "[a\\r\\n \t\u{a0}\u{2003}%O]{0,20}") {
            prop_assert_eq!(lines(&text).collect::<Vec<_>>(), text.lines().collect::<Vec<_>>());
            for line in text.lines() {
                prop_assert_eq!(trim_start(line), line.trim_start());
            }
        }

        /// Whenever the fast path accepts a block, the general parser reads the same block.
        #[test]
        fn plain_words_agrees_with_the_general_parser(text in "[NGXYZABFgxn ]{0,3}([NGXYZFHM] ?[-+]? ?[0-9.]{1,6} ?){0,5}[ \t]{0,2}") {
            if let Some(fast) = plain_words(text.as_bytes(), 1, 1) {
                prop_assert_eq!(fast, general(&text));
            }
        }
    }
}
