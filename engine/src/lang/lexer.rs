//! Tokens of one block. The lexer works on the upper-cased text of a block whose comments have
//! already been blanked out, so columns stay those of the source line.

use super::ast::Func;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Tok {
    Letter(u8),
    Num {
        value: f64,
        point: bool,
    },
    Hash,
    LBracket,
    RBracket,
    Comma,
    Assign,
    Plus,
    Minus,
    Star,
    Slash,
    Kw(Kw),
    /// A character that has no place in NC text.
    Bad(u8),
    /// Two decimal points in one number.
    BadNumber,
    /// More than 15 digits in one number.
    TooManyDigits,
    Eof,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kw {
    If,
    Goto,
    Then,
    While,
    Do,
    End,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
    Mod,
    Func(Func),
    Atan,
    Pow,
    Popen,
    Pclos,
    Dprnt,
    Bprnt,
}

/// Keywords, longest first so that a prefix match takes the longest one.
const KEYWORDS: &[(&[u8], Kw)] = &[
    (b"ROUND", Kw::Func(Func::Round)),
    (b"WHILE", Kw::While),
    (b"POPEN", Kw::Popen),
    (b"PCLOS", Kw::Pclos),
    (b"DPRNT", Kw::Dprnt),
    (b"BPRNT", Kw::Bprnt),
    (b"GOTO", Kw::Goto),
    (b"THEN", Kw::Then),
    (b"ASIN", Kw::Func(Func::Asin)),
    (b"ACOS", Kw::Func(Func::Acos)),
    (b"ATAN", Kw::Atan),
    (b"SQRT", Kw::Func(Func::Sqrt)),
    (b"AND", Kw::And),
    (b"XOR", Kw::Xor),
    (b"MOD", Kw::Mod),
    (b"SIN", Kw::Func(Func::Sin)),
    (b"COS", Kw::Func(Func::Cos)),
    (b"TAN", Kw::Func(Func::Tan)),
    (b"ABS", Kw::Func(Func::Abs)),
    (b"BIN", Kw::Func(Func::Bin)),
    (b"BCD", Kw::Func(Func::Bcd)),
    (b"FIX", Kw::Func(Func::Fix)),
    (b"FUP", Kw::Func(Func::Fup)),
    (b"EXP", Kw::Func(Func::Exp)),
    (b"POW", Kw::Pow),
    (b"ADP", Kw::Func(Func::Adp)),
    (b"END", Kw::End),
    (b"IF", Kw::If),
    (b"DO", Kw::Do),
    (b"EQ", Kw::Eq),
    (b"NE", Kw::Ne),
    (b"GT", Kw::Gt),
    (b"GE", Kw::Ge),
    (b"LT", Kw::Lt),
    (b"LE", Kw::Le),
    (b"OR", Kw::Or),
    (b"LN", Kw::Func(Func::Ln)),
];

/// Lexes one block: from the start of `text` up to a `;` or the end. Comments `( … )` are
/// skipped like spaces (the first one is remembered) and letters are read case-insensitively,
/// so the source line is never copied.
pub(super) struct Lexer<'a> {
    text: &'a [u8],
    pos: usize,
    /// Column of `text[0]` in the source line (1-based).
    col0: u32,
    peeked: Option<(Tok, u32)>,
    /// Byte range of the block's first comment (inside the parentheses).
    first_comment: Option<(usize, usize)>,
    /// Offset just after the `;` that ended the block, if one did.
    semicolon: Option<usize>,
}

impl<'a> Lexer<'a> {
    pub fn new(text: &'a [u8], col0: u32) -> Self {
        Lexer { text, pos: 0, col0, peeked: None, first_comment: None, semicolon: None }
    }

    /// The text of the block's first comment, trimmed.
    pub fn first_comment(&self) -> Option<String> {
        self.first_comment.map(|(a, b)| String::from_utf8_lossy(&self.text[a..b]).trim().to_string())
    }

    /// Where the next block of the same line starts, if a `;` ended this one.
    pub fn after_semicolon(&self) -> Option<usize> {
        self.semicolon
    }

    /// The raw bytes not yet consumed (used by DPRNT, whose argument is text).
    pub fn rest(&mut self) -> &'a [u8] {
        if let Some((_, col)) = self.peeked.take() {
            self.pos = (col - self.col0) as usize;
        }
        &self.text[self.pos..]
    }

    pub fn advance_raw(&mut self, n: usize) {
        debug_assert!(self.peeked.is_none());
        self.pos += n;
    }

    /// After an error: skip the rest of the block; where the next block starts, if any.
    pub fn skip_to_semicolon(&mut self) -> Option<usize> {
        self.peeked = None;
        loop {
            match self.lex().0 {
                Tok::Eof => return self.semicolon,
                _ => continue,
            }
        }
    }

    /// The name of a function another control has (`PRM[`, Syntec's `R_G53G59_COOR[`, `TIME[`)
    /// at column `col`: two or more letters, digits or underscores that follow a letter, then
    /// `[`; upper-cased. Not a keyword fivex knows: those are lexed as such before.
    pub fn function_name_at(&self, col: u32) -> Option<String> {
        let t = &self.text[(col.checked_sub(self.col0)? as usize).min(self.text.len())..];
        let len = t.iter().position(|c| !(c.is_ascii_alphanumeric() || *c == b'_')).unwrap_or(t.len());
        let rest = t[len..].iter().skip_while(|c| matches!(c, b' ' | b'\t'));
        let named = len >= 2 && t[0].is_ascii_alphabetic();
        (named && rest.clone().next() == Some(&b'[')).then(|| String::from_utf8_lossy(&t[..len]).to_ascii_uppercase())
    }

    /// The Syntec statement at column `col` that fivex does not have: `ALARM`, `MSG`, `SLEEP` or
    /// `WAIT` followed by `(`, or `EXIT` alone; its name as Syntec writes it (the handbook's
    /// §1.10, §4.9). `(` opens a comment for fivex, so such a block read as FANUC text is an
    /// address without a value.
    pub fn syntec_statement_at(&self, col: u32) -> Option<&'static str> {
        const CALLS: [(&str, &str); 4] =
            [("ALARM", "ALARM()"), ("MSG", "MSG()"), ("SLEEP", "SLEEP()"), ("WAIT", "WAIT()")];
        let t = &self.text[(col.checked_sub(self.col0)? as usize).min(self.text.len())..];
        let len = t.iter().position(|c| !c.is_ascii_alphabetic()).unwrap_or(t.len());
        let name = &t[..len];
        let next = t[len..].iter().find(|c| !matches!(c, b' ' | b'\t' | b'\r'));
        match next {
            Some(b'(') => CALLS.iter().find(|(n, _)| name.eq_ignore_ascii_case(n.as_bytes())).map(|(_, shown)| *shown),
            None | Some(b';') if name.eq_ignore_ascii_case(b"EXIT") => Some("EXIT"),
            _ => None,
        }
    }

    /// The digits of the number at column `col` that count towards an address's limit
    /// ([`increment_digits`]: `X1234567.` has ten, `X12.3456789` five).
    pub fn digits_at(&self, col: u32) -> usize {
        let start = col.saturating_sub(self.col0) as usize;
        increment_digits(self.text.get(start..).unwrap_or_default())
    }

    /// The column of the next token.
    pub fn col(&mut self) -> u32 {
        self.peek().1
    }

    pub fn peek(&mut self) -> (Tok, u32) {
        if self.peeked.is_none() {
            let t = self.lex();
            self.peeked = Some(t);
        }
        self.peeked.expect("just filled")
    }

    pub fn next_tok(&mut self) -> (Tok, u32) {
        let t = self.peek();
        self.peeked = None;
        t
    }

    fn skip_blanks(&mut self) {
        let t = self.text;
        while let Some(&c) = t.get(self.pos) {
            match c {
                b' ' | b'\t' | b'\r' => self.pos += 1,
                b'(' => {
                    // A comment runs to ')' or, unclosed, to the end of the line.
                    let start = self.pos + 1;
                    let end = t[start..].iter().position(|&b| b == b')').map_or(t.len(), |i| start + i);
                    self.first_comment.get_or_insert((start, end));
                    self.pos = (end + 1).min(t.len());
                }
                _ => return,
            }
        }
    }

    fn lex(&mut self) -> (Tok, u32) {
        self.skip_blanks();
        let t = self.text;
        let col = self.col0 + self.pos as u32;
        if self.semicolon.is_some() {
            return (Tok::Eof, col);
        }
        let Some(&c) = t.get(self.pos) else {
            return (Tok::Eof, col);
        };
        let tok = match c {
            b';' => {
                self.pos += 1;
                self.semicolon = Some(self.pos);
                return (Tok::Eof, col);
            }
            b'A'..=b'Z' | b'a'..=b'z' => return (self.letters(), col),
            b'0'..=b'9' | b'.' => return (self.number(), col),
            b'#' => Tok::Hash,
            b'[' => Tok::LBracket,
            b']' => Tok::RBracket,
            b',' => Tok::Comma,
            b'=' => Tok::Assign,
            b'+' => Tok::Plus,
            b'-' => Tok::Minus,
            b'*' => Tok::Star,
            b'/' => Tok::Slash,
            other => Tok::Bad(other),
        };
        self.pos += 1;
        (tok, col)
    }

    fn letters(&mut self) -> Tok {
        let t = self.text;
        let start = self.pos;
        let first = t[start].to_ascii_uppercase();
        if t.get(start + 1).is_some_and(|c| c.is_ascii_alphabetic()) {
            let end = t[start..].iter().position(|c| !c.is_ascii_alphabetic()).map_or(t.len(), |i| start + i);
            let run = &t[start..end];
            for (word, kw) in KEYWORDS {
                if run.len() >= word.len() && run[..word.len()].eq_ignore_ascii_case(word) {
                    self.pos += word.len();
                    return Tok::Kw(*kw);
                }
            }
        }
        self.pos += 1;
        Tok::Letter(first)
    }

    fn number(&mut self) -> Tok {
        let (tok, end) = number_at(self.text, self.pos);
        self.pos = end;
        tok
    }
}

/// The digits of the number `t` starts with, counted as a FANUC address counts them: in least
/// input increments of IS-B (0.001 mm, 0.001°), so a number with a decimal point has its integer
/// digits (less leading zeros) and three more; decimals beyond the increment are rounded, not
/// counted. (Inch input's increment, 0.0001, is not told apart: its limit is one digit wider.)
pub(super) fn increment_digits(t: &[u8]) -> usize {
    const DECIMALS: usize = 3;
    let len = t.iter().position(|c| !c.is_ascii_digit()).unwrap_or(t.len());
    let leading = t[..len].iter().take_while(|&&c| c == b'0').count();
    let point = t.get(len) == Some(&b'.');
    len - leading + if point { DECIMALS } else { 0 }
}

/// The number starting at `pos` (digits and at most one point) and the offset after it.
pub(super) fn number_at(t: &[u8], start: usize) -> (Tok, usize) {
    const POW10: [f64; 16] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];
    // The digits from `pos` on, added to `mantissa`; returns the offset after them.
    let digits_from = |mut pos: usize, mantissa: &mut u64| {
        while let Some(d) = t.get(pos).map(|c| c.wrapping_sub(b'0')).filter(|&d| d < 10) {
            *mantissa = mantissa.wrapping_mul(10).wrapping_add(d as u64);
            pos += 1;
        }
        pos
    };
    let mut mantissa = 0u64;
    let int_end = digits_from(start, &mut mantissa);
    let point = t.get(int_end) == Some(&b'.');
    let (pos, frac) = if point {
        let end = digits_from(int_end + 1, &mut mantissa);
        if t.get(end) == Some(&b'.') {
            return (Tok::BadNumber, end);
        }
        (end, end - int_end - 1)
    } else {
        (int_end, 0)
    };
    // More digits than an f64 holds exactly: FANUC's "too many digits".
    if int_end - start + frac > 15 {
        return (Tok::TooManyDigits, pos);
    }
    // Both operands are exact, so one division is correctly rounded, like `str::parse`. (Via
    // i64: converting a u64 to f64 takes a dozen instructions, an i64 one.)
    let m = mantissa as i64 as f64;
    let value = if frac == 0 { m } else { m / POW10[frac] };
    // "." alone is zero with a decimal point, as FANUC reads `X.`.
    (Tok::Num { value, point }, pos)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok> {
        let mut l = Lexer::new(s.as_bytes(), 1);
        let mut v = vec![];
        loop {
            let (t, _) = l.next_tok();
            if t == Tok::Eof {
                return v;
            }
            v.push(t);
        }
    }

    #[test]
    fn keywords_and_letters() {
        assert_eq!(
            toks("IF[#1GE2]GOTO10"),
            vec![
                Tok::Kw(Kw::If),
                Tok::LBracket,
                Tok::Hash,
                Tok::Num { value: 1.0, point: false },
                Tok::Kw(Kw::Ge),
                Tok::Num { value: 2.0, point: false },
                Tok::RBracket,
                Tok::Kw(Kw::Goto),
                Tok::Num { value: 10.0, point: false },
            ]
        );
        assert_eq!(toks("G43.4")[1], Tok::Num { value: 43.4, point: true });
        assert_eq!(toks("X.")[1], Tok::Num { value: 0.0, point: true });
        assert_eq!(toks("X1.2.3")[1], Tok::BadNumber);
    }

    proptest::proptest! {
        /// Numbers read exactly as `str::parse` reads them, up to 15 digits; more is an error.
        #[test]
        fn numbers_read_as_str_parse_does(text in "[0-9]{0,17}(\\.[0-9]{0,17})?[.X]?") {
            let (tok, end) = number_at(text.as_bytes(), 0);
            let number = &text[..end];
            let digits = number.bytes().filter(u8::is_ascii_digit).count();
            match tok {
                Tok::Num { value, point } => {
                    proptest::prop_assert!(digits <= 15);
                    proptest::prop_assert_eq!(point, number.contains('.'));
                    let expected = if number == "." || number.is_empty() { 0.0 } else { number.parse::<f64>().unwrap() };
                    proptest::prop_assert_eq!(value, expected);
                    proptest::prop_assert!(!text[end..].starts_with(|c: char| c.is_ascii_digit()));
                }
                Tok::TooManyDigits => proptest::prop_assert!(digits > 15),
                Tok::BadNumber => proptest::prop_assert!(text[end..].starts_with('.') && number.contains('.')),
                other => proptest::prop_assert!(false, "{:?}", other),
            }
        }
    }
}
