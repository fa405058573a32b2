//! The syntax tree of an NC file.

use super::diag::Diagnostic;

/// A whole file: one or more programs. The first is the main program.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct File {
    pub programs: Vec<Program>,
    /// Every diagnostic of the file, in source order.
    pub diagnostics: Vec<Diagnostic>,
    /// Number of lines read (the next part of a file starts at `first_line + lines`).
    pub lines: u32,
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Program {
    /// The `O` number; `None` for a file's single anonymous program.
    pub number: Option<u32>,
    /// 1-based line of the `O` block (or of the first block).
    pub line: u32,
    pub blocks: Vec<Block>,
}

impl Program {
    /// The program without its blocks.
    pub fn clone_header(&self) -> Program {
        Program { number: self.number, line: self.line, blocks: Vec::new() }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// 1-based line in the file.
    pub line: u32,
    /// 1-based column where the block's text starts.
    pub col: u32,
    /// `/` or `/n` at the start: the optional block skip switch (1 for a plain `/`).
    pub block_delete: Option<u8>,
    /// Sequence number `N…`.
    pub n: Option<u32>,
    pub kind: BlockKind,
    /// Text of the first comment in the block, used as the message of `#3000`/`#3006`.
    pub comment: Option<String>,
}

impl Block {
    /// Skipped with the block delete switch `on`: a `/` or `/1` block. `/2`…`/9` belong to the
    /// FANUC additional optional block skip switches 2–9, which fivex does not model (they stay
    /// off): such a block runs whatever switch 1 says.
    pub fn deleted(&self, on: bool) -> bool {
        on && self.block_delete == Some(1)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum BlockKind {
    /// Nothing but a sequence number and/or comments.
    Empty,
    /// An NC statement: address words in source order (up to four stored inline: most blocks
    /// need no allocation of their own).
    Words(Words),
    /// `#i = expr`
    Assign { var: Expr, value: Expr },
    /// `IF [cond] GOTO n`
    IfGoto { cond: Expr, target: Expr },
    /// `IF [cond] THEN #i = expr`
    IfThen { cond: Expr, var: Expr, value: Expr },
    /// `[cond] words`: NC words carried out only when the condition holds. The Haas NGC's
    /// conditional `[cond] M99 P<n>`; the interpreter refuses every other form and dialect.
    IfWords { cond: Expr, words: Words },
    /// `GOTO n`
    Goto(Expr),
    /// `WHILE [cond] DO m`, or `DO m` alone (cond `None`: loop forever)
    Do { cond: Option<Expr>, id: u8 },
    /// `END m`
    End { id: u8 },
    /// `POPEN`, `PCLOS`, `DPRNT[…]`, `BPRNT[…]`: external output.
    Output(Output),
    /// A block that could not be parsed; raising its alarm is deferred until it is executed.
    Error(Diagnostic),
    /// Text the Syntec controller reads with a meaning fivex does not perform
    /// (`docs/dialects.md`, "The Syntec macro language"): refused in the Syntec dialect, read
    /// as before in the others.
    SyntecOnly(Box<SyntecOnly>),
}

/// What a [`BlockKind::SyntecOnly`] block is in each dialect.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntecOnly {
    /// The Syntec dialect's refusal: not built, naming the function.
    pub syntec: Diagnostic,
    /// What the FANUC and Haas dialects read there: nothing (a `%` line, a comment), or a block
    /// they refuse with this diagnostic (`ALARM(…)`: the address A without a value).
    pub others: Option<Diagnostic>,
    /// The Syntec dialect refuses the whole file here, before anything of it runs (the
    /// MACRO-format line `%@MACRO`, wherever it stands: `interp::Loaded::macro_format`).
    pub whole_file: bool,
}

impl SyntecOnly {
    /// The diagnostic `dialect` raises at the block, if any.
    pub fn refusal(&self, dialect: crate::dialect::Dialect) -> Option<&Diagnostic> {
        match dialect {
            crate::dialect::Dialect::Syntec => Some(&self.syntec),
            _ => self.others.as_ref(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Output {
    Open,
    Close,
    /// DPRNT: text pieces and variables with their digit format.
    Print(Vec<PrintItem>),
    /// BPRNT: binary output; fivex records it like DPRNT.
    BinaryPrint(Vec<PrintItem>),
}

#[derive(Debug, Clone, PartialEq)]
pub enum PrintItem {
    Text(String),
    /// `#i[ab]`: a digits before and b digits after the point.
    Var {
        var: Expr,
        int_digits: u8,
        frac_digits: u8,
    },
}

/// The words of an NC statement.
pub type Words = smallvec::SmallVec<[Word; 4]>;

/// One address word: a letter and its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Word {
    /// The address in upper case; a comma address (`,C` `,R` `,A` `,L`) in lower case, and so
    /// are the I, J, K that follow `,L` (FANUC's `,L2 I J K`, the surface normal of cutting
    /// point control), which are not the block's own I, J, K.
    pub letter: u8,
    pub value: WordValue,
    /// 1-based column of the letter.
    pub col: u32,
}

#[derive(Debug, Clone, PartialEq)]
pub enum WordValue {
    /// A literal number and whether it was written with a decimal point.
    Number { value: f64, decimal_point: bool },
    /// `#i`, `-#i`, `[expr]`: evaluated when the block runs; a vacant result omits the word.
    /// Boxed: most words are plain numbers, and this keeps every `Word` small.
    Expr(Box<Expr>),
}

/// Expressions. Variables are read when the expression is evaluated.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A number and whether it was written with a decimal point (Syntec's division tells an
    /// integer by it, `interp::expr::eval_typed`).
    Num {
        value: f64,
        decimal_point: bool,
    },
    /// `#n` with a literal number (the common, fast case).
    Var(u32),
    /// `#[expr]`
    IndirectVar(Box<Expr>),
    /// Unary minus. Applied to a lone variable it keeps vacancy (`-#1` with `#1` vacant is vacant).
    Neg(Box<Expr>),
    /// `[expr]`: grouping; kept so a bracketed lone variable keeps its vacancy.
    Bracket(Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    Func(Func, Box<Expr>),
    /// `ATAN[a]/[b]`, `ATAN[a,b]`, `POW[a,b]`
    Func2(Func2, Box<Expr>, Box<Expr>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Mul,
    Div,
    And,
    Mod,
    Add,
    Sub,
    Or,
    Xor,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
}

impl BinOp {
    /// Binding strength: higher binds tighter.
    pub fn precedence(self) -> u8 {
        use BinOp::*;
        match self {
            Mul | Div | And | Mod => 3,
            Add | Sub | Or | Xor => 2,
            Eq | Ne | Gt | Ge | Lt | Le => 1,
        }
    }

    pub fn is_comparison(self) -> bool {
        self.precedence() == 1
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    /// Single-argument arc tangent `ATAN[a]`.
    Atan,
    Sqrt,
    Abs,
    Bin,
    Bcd,
    Round,
    Fix,
    Fup,
    Ln,
    Exp,
    Adp,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func2 {
    Atan,
    Pow,
}
