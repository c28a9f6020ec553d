# reel: the two commands of the README.
#   make demo   installs what is missing, builds Release, renders the headline films into
#               render_out/ (the flying carpet, the school of fish, then Go Fish!)
#   make films  the same for every film in scenes/
#   make test   installs what is missing, builds Release, runs every test through ctest
PRESET ?= release
JOBS   ?= $(shell nproc)
BUILD  := build/$(PRESET)
REEL   := $(BUILD)/reel
DEMO_SCENES := scenes/flying_carpet.json scenes/school.json scenes/go_fish.json
FILM_SCENES := $(sort $(wildcard scenes/*.json))

.PHONY: all deps configure build demo films test clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build --preset $(PRESET) -j $(JOBS)

# Renders each scene of $(1) into render_out/NAME.mp4, stopping at the first failure.
render_all = @mkdir -p render_out && for s in $(1); do \
	  n=$$(basename $$s .json); \
	  echo "reel render $$s -o render_out/$$n.mp4"; \
	  $(REEL) render $$s -o render_out/$$n.mp4 || exit $$?; \
	done

demo: build
	$(call render_all,$(DEMO_SCENES))

films: build
	$(call render_all,$(FILM_SCENES))

test: build
	@cd $(BUILD) && ctest -j $(JOBS) --output-on-failure --no-tests=error

clean:
	rm -rf build
