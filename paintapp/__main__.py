from paintapp.cli import main

raise SystemExit(main())
