export function App() {
  return <h1>fivex</h1>;
}
