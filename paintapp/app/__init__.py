"""The interactive painting app (``paintapp paint``): a Qt window (PySide6) with a moderngl canvas.

- :mod:`.launch` display check, Qt/OpenGL set-up, recovery on start; :mod:`.window` the main
  window: menus, shortcuts, timers (the render loop), glue;
- :mod:`.canvas_widget` the canvas (drawn offscreen with OpenGL, shown as an image) and its
  tablet/mouse events; :mod:`.input` turns them into stylus samples;
- :mod:`.worker` the simulation thread, :mod:`.sim_process` it in a process of its own;
  :mod:`.warmup` the scratch stroke before the first; :mod:`.actions` the controls' commands;
- :mod:`.haptic_link` the device and the 1 kHz servo loop; :mod:`.shared` what threads exchange;
- :mod:`.history` undo/redo, :mod:`.journal` the stroke recording, :mod:`.recovery` autosave,
  :mod:`.document` the canvas's file (new, open, save, save as, export);
- :mod:`.hud`, :mod:`.controls`, :mod:`.shortcuts` the heads-up display, controls panel and
  shortcut table with its help overlay; :mod:`.settings`, :mod:`.options` typed settings;
- :mod:`.slab`, :mod:`.slab_widget` the mixing slab and its widget; :mod:`.explore_launch`,
  :mod:`.explore_window` ``paintapp explore``'s window: a stored flow, its probe, its force.

Qt is imported only by the modules that draw or handle events: the command line works without it.
"""
