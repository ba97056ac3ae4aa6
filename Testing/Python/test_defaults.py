"""Documented defaults stay aligned: for every SourceProxy of the ParaView
plugin XML with a class attribute, every Int/Double/StringVectorProperty with
a Set* command and default_values must equal Get*() of a fresh instance of
the class (read through the Python wrapping). Every command the XML names
must exist on the class."""
import math
import os
import sys
import xml.etree.ElementTree as ET

import digitalgeometry

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


HERE = os.path.dirname(os.path.abspath(__file__))
XML = os.environ.get("DG_PLUGIN_XML",
                     os.path.join(HERE, "..", "..", "ParaViewPlugin", "DigitalGeometry.xml"))
VECTOR_PROPERTIES = ("IntVectorProperty", "DoubleVectorProperty", "StringVectorProperty")
# The XML defaults of these are not plain values of a Set/Get pair.
SKIPPED_COMMANDS = ("SetInputArrayToProcess",)
MIN_COMPARED = 30
REL_TOL = 1e-12


def doubles_equal(a, b):
    if math.isnan(a) or math.isnan(b):
        return False
    if a == b:
        return True
    return abs(a - b) <= REL_TOL * max(abs(a), abs(b))


def same(kind, xml_text, value):
    """One element: the XML text against a getter's value (booleans as 0/1)."""
    if kind == "IntVectorProperty":
        if isinstance(value, bool):  # bool getters; vtkTypeBool ones give int
            value = int(value)
        return isinstance(value, int) and value == int(xml_text)
    if kind == "DoubleVectorProperty":
        return (isinstance(value, (int, float)) and not isinstance(value, bool)
                and doubles_equal(float(value), float(xml_text)))
    return isinstance(value, str) and value == xml_text


# The comparison itself must be able to fail (no vacuous pass).
check(same("DoubleVectorProperty", "0.1", 0.1)
      and same("DoubleVectorProperty", "1e-8", 1e-8)
      and not same("DoubleVectorProperty", "0.1", 0.1 * (1 + 1e-9))
      and not same("DoubleVectorProperty", "1e+300", 1e+299)
      and same("IntVectorProperty", "1", True)
      and not same("IntVectorProperty", "0", True)
      and not same("IntVectorProperty", "3", 3.5)
      and same("StringVectorProperty", "IINormals", "IINormals")
      and not same("StringVectorProperty", "IINormals", None),
      "the comparison accepts equal values and rejects different ones")

check(os.path.isfile(XML), "plugin XML found: %s" % os.path.normpath(XML))
if not os.path.isfile(XML):
    print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
    sys.exit(1)

root = ET.parse(XML).getroot()
proxies = [p for p in root.iter("SourceProxy") if p.get("class")]
check(len(proxies) >= 5, "%d SourceProxy elements with a class" % len(proxies))

compared = {}
skipped = []
for proxy in proxies:
    pname, cname = proxy.get("name"), proxy.get("class")
    cls = getattr(digitalgeometry, cname, None)
    check(cls is not None, "%s: class %s is in the digitalgeometry package" % (pname, cname))
    if cls is None:
        continue
    obj = cls()  # a fresh instance: its values are the C++ defaults
    compared[pname] = 0
    for prop in proxy:
        tag = prop.tag
        command = prop.get("command")
        name = prop.get("name")
        where = "%s (%s).%s" % (pname, cname, name)
        if command is None:
            continue
        # Every command the XML names must exist on the class.
        if tag not in VECTOR_PROPERTIES or not command.startswith("Set"):
            check(hasattr(obj, command), "%s: %s has %s()" % (where, cname, command))
            if tag in VECTOR_PROPERTIES:
                skipped.append("%s: command %s is not a Set command" % (where, command))
            continue
        skip = None
        if command in SKIPPED_COMMANDS:
            skip = "%s (default %r not compared)" % (command, prop.get("default_values"))
        elif "filename" in name.lower() or "filename" in command.lower():
            skip = "file name property %s" % command
        elif prop.get("default_values") is None:
            skip = "%s has no default_values" % command
        if skip:
            check(hasattr(obj, command), "%s: %s has %s()" % (where, cname, command))
            skipped.append("%s: %s" % (where, skip))
            continue
        getter = "Get" + command[3:]
        missing = [m for m in (command, getter) if not hasattr(obj, m)]
        if missing:
            check(False, "%s: %s has no %s" % (where, cname, " nor ".join(m + "()" for m in missing)))
            continue
        defaults = prop.get("default_values")
        n = int(prop.get("number_of_elements", "1"))
        delimiter = prop.get("default_values_delimiter")
        if tag == "StringVectorProperty":
            values = defaults.split(delimiter) if delimiter else [defaults]
        else:
            values = defaults.split(delimiter) if delimiter else defaults.split()
        if len(values) != n:
            check(False, "%s: %d default value(s) %r for number_of_elements %d"
                  % (where, len(values), defaults, n))
            continue
        actual = getattr(obj, getter)()
        if n == 1:
            ok = same(tag, values[0], actual)
        else:
            ok = isinstance(actual, (tuple, list)) and len(actual) == n
            ok = ok and all(same(tag, values[i], actual[i]) for i in range(n))
        check(ok, "%s: XML default %r, C++ %s() of a new instance %r"
              % (where, defaults, getter, actual))
        compared[pname] += 1

for s in skipped:
    print("note: skipped " + s)

# Properties the class declares (a Set/Get pair of its own) that the XML does
# not expose: information only.
for proxy in proxies:
    cls = getattr(digitalgeometry, proxy.get("class"), None)
    if cls is None:
        continue
    exposed = {p.get("command") for p in proxy if p.get("command")}
    own = sorted(k for k in cls.__dict__
                 if k.startswith("Set") and "Get" + k[3:] in cls.__dict__ and k not in exposed)
    if own:
        print("note: %s (%s) not in the XML: %s" % (proxy.get("name"), proxy.get("class"),
                                                     ", ".join(own)))

total = sum(compared.values())
for pname, count in compared.items():
    print("summary: %-20s %2d properties compared" % (pname, count))
print("summary: %-20s %2d properties compared, %d skipped" % ("total", total, len(skipped)))
check(total >= MIN_COMPARED, "%d properties compared (at least %d expected)" % (total, MIN_COMPARED))
filters = [p.get("name") for p in proxies if p.get("name") in compared and p.get("name") != "DGtalVolReader"]
check(all(compared[f] > 0 for f in filters),
      "every filter proxy has compared properties (%s)"
      % ", ".join("%s %d" % (f, compared[f]) for f in filters))

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
