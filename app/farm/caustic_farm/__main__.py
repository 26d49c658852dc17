from caustic_farm.cli import main

raise SystemExit(main())
