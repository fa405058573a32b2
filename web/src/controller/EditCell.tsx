// A table cell's value, edited in place: committed on Enter or when the field loses focus.
// Uncontrolled on purpose: the page re-renders with every position frame, and a controlled
// field would put the shown value back under the operator's typing. A new `value` from the
// service replaces the field (its key changes).

export function EditCell({ value, onCommit, wide = false }: { value: string; onCommit: (text: string) => void; wide?: boolean }) {
  return (
    <input
      class={wide ? "wide num" : "num"}
      key={value}
      defaultValue={value}
      onChange={(e) => onCommit(e.currentTarget.value)}
      onKeyDown={(e) => e.key === "Enter" && e.currentTarget.blur()}
    />
  );
}
