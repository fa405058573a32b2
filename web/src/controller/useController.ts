// One controller as the page sees it: its status, machine, the latest position frame, alarms,
// variables, operator messages, notices and what is clamped on the table, kept current by the
// controller's websocket.
import { useCallback, useEffect, useRef, useState } from "preact/hooks";
import { api, errorText, liveSocket, must, wsUrl, type AlarmInfo, type ControllerMessage, type Frame, type Machine, type Status } from "../api/client";
import { workpieceOf, type Workpiece } from "./workpiece";

/// A notice as the stream gives it: its line is in the stored program `program` (null: MDI's own).
export type LocatedNotice = Omit<Extract<ControllerMessage, { type: "notice" }>, "type">;

export type Live = {
  status: Status | null;
  machine: Machine | null;
  frame: Frame | null;
  alarms: AlarmInfo[];
  variables: Record<string, number | null>;
  messages: string[];
  /// Blocks run by a rule of fivex's own (the last 20), as the stream's `notice` messages told.
  notices: LocatedNotice[];
  /// What is clamped on the table (the snapshot's, then every `workpiece` message); null until
  /// the stream's snapshot.
  workpiece: Workpiece | null;
  connected: boolean;
  error: string | null;
  /// Called with every position frame as it arrives (the 3D trace), not throttled.
  onFrame: (f: (frame: Frame) => void) => () => void;
  /// Carry out an operator action and take the status it answers (throws `ApiError`).
  act: Act;
};

/// An operator action: a call whose answer is the controller's status.
export type Act = (call: () => Promise<{ data?: Status; error?: unknown; response: Response }>) => Promise<void>;

export function useController(id: string): Live {
  const [status, setStatus] = useState<Status | null>(null);
  const [machine, setMachine] = useState<Machine | null>(null);
  const [frame, setFrame] = useState<Frame | null>(null);
  const [alarms, setAlarms] = useState<AlarmInfo[]>([]);
  const [variables, setVariables] = useState<Record<string, number | null>>({});
  const [messages, setMessages] = useState<string[]>([]);
  const [notices, setNotices] = useState<LocatedNotice[]>([]);
  const [workpiece, setWorkpiece] = useState<Workpiece | null>(null);
  const [connected, setConnected] = useState(false);
  const [error, setError] = useState<string | null>(null);
  const listeners = useRef(new Set<(f: Frame) => void>());
  const onFrame = useCallback((f: (frame: Frame) => void) => {
    listeners.current.add(f);
    return () => {
      listeners.current.delete(f);
    };
  }, []);
  /// Stream events (snapshot, state, alarm) seen so far: an action's answer must not undo one
  /// that arrived while the request was under way.
  const events = useRef(0);
  const act = useCallback<Act>(async (call) => {
    const seen = events.current;
    const s = await must(call());
    if (events.current === seen) {
      setStatus(s);
      setAlarms(s.alarms);
    } else {
      // The stream already told something newer about the run state, mode and alarms.
      setStatus((now) => (now ? { ...s, run_state: now.run_state, mode: now.mode, program: now.program, alarms: now.alarms } : s));
    }
  }, []);

  useEffect(() => {
    let latest: Frame | null = null;
    let scheduled = false;
    must(api.GET("/api/v1/controllers/{id}/machine", { params: { path: { id } } })).then(setMachine, (e) => setError(errorText(e)));
    must(api.GET("/api/v1/controllers/{id}", { params: { path: { id } } })).then(
      (s) => {
        setStatus(s);
        setAlarms(s.alarms);
      },
      (e) => setError(errorText(e)),
    );
    const socket = liveSocket<ControllerMessage>(
      () => wsUrl(`/api/v1/controllers/${encodeURIComponent(id)}/stream`, { rate: 30 }),
      (msg) => {
        const told = workpieceOf(msg);
        if (told) setWorkpiece(told);
        switch (msg.type) {
          case "snapshot": {
            events.current++;
            setStatus(msg.controller);
            setAlarms(msg.controller.alarms);
            setVariables(msg.variables);
            break;
          }
          case "position": {
            latest = msg;
            for (const f of listeners.current) f(latest);
            // The panel repaints once per animation frame at most.
            if (!scheduled) {
              scheduled = true;
              requestAnimationFrame(() => {
                scheduled = false;
                setFrame(latest);
              });
            }
            break;
          }
          case "state":
            events.current++;
            setStatus((s) => (s ? { ...s, run_state: msg.run_state, mode: msg.mode, program: msg.program } : s));
            break;
          case "alarm":
            events.current++;
            setAlarms(msg.active);
            setStatus((s) => (s ? { ...s, alarms: msg.active } : s));
            break;
          case "variables":
            setVariables((v) => ({ ...v, ...msg.changes }));
            break;
          case "message":
            setMessages((m) => [...m.slice(-19), msg.text]);
            break;
          case "notice": {
            const { type: _, ...notice } = msg;
            setNotices((n) => [...n.slice(-19), notice]);
            break;
          }
        }
      },
      setConnected,
    );
    return () => socket.close();
  }, [id]);

  return {
    status,
    machine,
    frame,
    alarms,
    variables,
    messages,
    notices,
    workpiece,
    connected,
    error,
    onFrame,
    act,
  };
}
