"""The interactive painting app (``paintapp paint``): a Qt window (PySide6) with a moderngl canvas.

Modules, one job each:

- :mod:`.launch` display check, Qt/OpenGL set-up, recovery on start, the window;
- :mod:`.window` the main window: menus, shortcuts, timers (the render loop), glue;
- :mod:`.canvas_widget` the canvas (drawn offscreen with OpenGL, shown as an image) and its
  tablet/mouse events; :mod:`.input` turns them into stylus samples;
- :mod:`.worker` the simulation thread; :mod:`.actions` the commands it runs for the controls;
- :mod:`.haptic_link` the device and the 1 kHz servo thread;
- :mod:`.shared` what the threads exchange; :mod:`.history` undo/redo; :mod:`.journal` the stroke
  recording; :mod:`.recovery` autosave; :mod:`.files` open/save/export;
- :mod:`.hud`, :mod:`.controls`, :mod:`.shortcuts` the heads-up display, the controls panel and
  the shortcut table with its help overlay; :mod:`.settings`, :mod:`.options` typed settings.

Qt is imported only by the modules that draw or handle events, so the command line stays usable
without it.
"""
