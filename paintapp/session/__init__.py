"""The session joins the whole flow: stylus samples -> brush tip -> paint grid -> canvas, forces
out to the servo loop (:mod:`.painting`); replaying stroke files on a virtual clock through the
same path (:mod:`.playback`); the files a replay writes (:mod:`.outputs`); how far two replays
differ (:mod:`.compare`) and how strongly each stroke carries its own step (:mod:`.comb`);
the devices a replay can play on (:mod:`.replay_devices`); and ``--explain``'s account of what
ran and why (:mod:`.explain`). See ``docs/design/architecture.md`` for the module behind each
arrow."""
