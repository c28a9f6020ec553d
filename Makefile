# reel: the two commands of the README.
#   make demo   installs what is missing, builds Release, renders the headline films into
#               render_out/ (the flying carpet, then the school of fish)
#   make films  the same for every film in scenes/
#   make test   installs what is missing, builds Release, runs every test through ctest
PRESET ?= release
JOBS   ?= $(shell nproc)
BUILD  := build/$(PRESET)
REEL   := $(BUILD)/reel
DEMO_SCENES := scenes/flying_carpet.json scenes/school.json
FILM_SCENES := $(sort $(wildcard scenes/*.json))

.PHONY: all deps configure build demo films test clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build --preset $(PRESET) -j $(JOBS)

demo: build
	@mkdir -p render_out
	@for s in $(DEMO_SCENES); do \
	  n=$$(basename $$s .json); \
	  echo "reel render $$s -o render_out/$$n.mp4"; \
	  $(REEL) render $$s -o render_out/$$n.mp4 || exit $$?; \
	done

films: build
	@mkdir -p render_out
	@for s in $(FILM_SCENES); do \
	  n=$$(basename $$s .json); \
	  echo "reel render $$s -o render_out/$$n.mp4"; \
	  $(REEL) render $$s -o render_out/$$n.mp4 || exit $$?; \
	done

test: build
	@cd $(BUILD) && ctest -j $(JOBS) --output-on-failure

clean:
	rm -rf build
