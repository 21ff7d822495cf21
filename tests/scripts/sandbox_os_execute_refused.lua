-- The sandbox has no os.execute (nor os.exit, os.getenv, os.remove, ...): the call is
-- refused at its line with a message that says why, and no shell runs.
-- expect-exit: 2
-- expect-stderr: sandbox_os_execute_refused.lua:7: os.execute is not available in a scene script
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
os.execute("touch /tmp/seiche_sandbox_escaped")
