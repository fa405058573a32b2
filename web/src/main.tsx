import { render } from "preact";
import { App } from "./app";
import { adoptTokenFromAddress } from "./api/auth";
import "./style.css";

adoptTokenFromAddress();
render(<App />, document.getElementById("app")!);
