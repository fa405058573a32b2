// A table cell's value, edited in place: committed on Enter or when the field loses focus.
// Uncontrolled on purpose: the page re-renders with every position frame, and a controlled
// field would put the shown value back under the operator's typing. A new `value` from the
// service replaces the field (its key changes). A commit that is not taken (`onCommit` answers
// false: the text is no number, or the service refused it) puts the stored value back in the
// field, so the cell never shows a value the service does not hold; the reason is the caller's
// to show.
import { useRef } from "preact/hooks";

export function EditCell({
  value,
  onCommit,
  wide = false,
}: {
  value: string;
  onCommit: (text: string) => boolean | void | Promise<boolean | void>;
  wide?: boolean;
}) {
  const field = useRef<HTMLInputElement>(null);
  const shown = useRef(value);
  shown.current = value;
  return (
    <input
      ref={field}
      class={wide ? "wide num" : "num"}
      key={value}
      defaultValue={value}
      onChange={async (e) => {
        const taken = await onCommit(e.currentTarget.value);
        if (taken === false && field.current) field.current.value = shown.current;
      }}
      onKeyDown={(e) => e.key === "Enter" && e.currentTarget.blur()}
    />
  );
}
