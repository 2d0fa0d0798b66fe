# feeddrive — build the FMU, run the main job, test, benchmark.
#   make / make fmu   build build/LinearMotorFeedDrive.fmu (and its copy inside the package,
#                     python/feeddrive/, git-ignored: the package data of installs and wheels)
#   make run          set-up, FMU, the paper's closed-loop reproductions, report (prints the tables)
#   make test         set-up, FMU, every test
#   make bench        benchmark table (build/bench.md)
#   make wheel        build/feeddrive-*.whl carrying the FMU
MODEL      := LinearMotorFeedDrive
PYTHON     ?= python3
VENV       := .venv
PY         := $(VENV)/bin/python
BUILD      := build
GEN        := $(BUILD)/gen
FMU        := $(BUILD)/$(MODEL).fmu
PKG_FMU    := python/feeddrive/$(MODEL).fmu
SHARED     ?= ../shared
TESTS_C    := $(CURDIR)/$(BUILD)/tests_c
SO         := $(BUILD)/binaries/linux64/$(MODEL).so
CC         ?= cc
FMU_CFLAGS := -std=c99 -O3 -fno-math-errno -fPIC -Wall -Wextra -Werror -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE
SRC_C      := $(filter-out %gen_vars.py,$(wildcard fmu_src/*.c))
SRC_H      := $(wildcard fmu_src/*.h)
STAMP      := $(VENV)/.installed

.PHONY: all fmu run test bench wheel clean venv
all: fmu
fmu: $(FMU) $(PKG_FMU)
venv: $(STAMP)

$(STAMP): python/pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e 'python[test]'
	touch $@

$(BUILD)/fmi_include: $(STAMP)
	mkdir -p $(BUILD)
	$(PY) -c "import fmpy, os; print(os.path.join(os.path.dirname(fmpy.__file__), 'c-code'))" > $@

$(GEN)/model_vars.h $(GEN)/model_vars.c: modelDescription.xml fmu_src/gen_vars.py $(STAMP)
	$(PY) fmu_src/gen_vars.py modelDescription.xml $(GEN)

$(SO): $(SRC_C) $(SRC_H) $(GEN)/model_vars.h $(GEN)/model_vars.c $(BUILD)/fmi_include
	mkdir -p $(dir $@)
	$(CC) $(FMU_CFLAGS) $(CFLAGS) -shared -fvisibility=default -I fmu_src -I $(GEN) -I "$$(cat $(BUILD)/fmi_include)" \
	    -o $@ $(SRC_C) $(GEN)/model_vars.c -lm
	@! (ldd $@ | grep -v -E 'linux-vdso|libc\.so|libm\.so|ld-linux|not a dynamic' | grep -q .) || \
	    (echo "error: $@ links more than libc/libm:"; ldd $@; exit 1)

$(FMU): $(SO) modelDescription.xml
	$(PY) tools/package_fmu.py --xml modelDescription.xml --so $(SO) \
	    --sources fmu_src $(GEN) --out $@

$(PKG_FMU): $(FMU)
	cp $< $@

run: fmu
	$(PY) -m feeddrive.cli run --shared $(SHARED) --force

test: fmu
	$(PY) -m pytest -q tests

# the C benchmark hosts are test code (tests/c); built here and handed to the benchmark
bench: fmu
	$(MAKE) -s -C tests/c $(TESTS_C)/bench_cs $(TESTS_C)/cycles
	$(PY) -m feeddrive.bench --out $(BUILD)/bench.md --bench-cs $(TESTS_C)/bench_cs \
	    --cycles $(TESTS_C)/cycles --library $(SO)

wheel: $(PKG_FMU)
	rm -rf $(BUILD)/feeddrive-*.whl python/build
	$(PY) -m pip wheel -q --no-deps -w $(BUILD) ./python

clean:
	rm -rf $(BUILD) $(PKG_FMU)
