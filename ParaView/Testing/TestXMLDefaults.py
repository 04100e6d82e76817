"""The server-manager XML of the plugin against the C++ classes (standalone build, Debian's
/usr/bin/python3 with the `terroir` package): every property's default is the class's default
(read back with its getter from a new object), every range is the class's clamp range where it
has one, every enumeration entry names the value its SetXTo<Entry>() sets, and every reader,
filter and writer class of the modules has a proxy.
    TestXMLDefaults.py PLUGIN_XML_DIR"""
import glob
import math
import os
import sys
import xml.etree.ElementTree as ET

import terroir

# Classes without a proxy, and why.
NO_PROXY = {
    'vtkTerroirClimateReader': 'not an algorithm: a table of monthly numbers for C++ and the CLI',
    'vtkTerroirImageAlgorithm': 'abstract base: its properties are in every filter proxy',
    'vtkTerroirImageWriter': 'abstract base: its properties are in every writer proxy',
    'vtkTerroirKMeansGPU': 'the GPU engine of vtkTerroirKMeans (its Backend property)',
    'vtkTerroirWaterFlowGPU': 'the GPU path of vtkTerroirWaterFlow (its Backend property)',
}
# Properties whose setter is not a plain Set<Name>(value): checked below by behaviour.
SPECIAL = {'SetInputArrayToProcess', 'SetFillAndSlopeRule', 'AddFeature', 'AddSeedPoint',
           'SetFileName'}
failures = []


def fail(message):
    failures.append(message)
    print('FAIL', message)


def proxies(xml_dir):
    """Every proxy element by (group, name), and the property elements each has, bases first."""
    found = {}
    for path in sorted(glob.glob(os.path.join(xml_dir, '*.xml'))):
        for group in ET.parse(path).getroot().iter('ProxyGroup'):
            for proxy in group:
                found[(group.get('name'), proxy.get('name'))] = proxy
    result = {}
    for key, proxy in found.items():
        props = []
        base = (proxy.get('base_proxygroup'), proxy.get('base_proxyname'))
        if base in found:
            props += [p for p in found[base] if p.get('command')]
        props += [p for p in proxy if p.get('command')]
        result[key] = (proxy, props)
    return result


def values(text, kind):
    convert = {'IntVectorProperty': int, 'IdTypeVectorProperty': int,
               'DoubleVectorProperty': float}.get(kind, str)
    return [convert(v) for v in text.split()]


def check_property(cls, obj, prop):
    command = prop.get('command')
    name = '%s.%s' % (cls, prop.get('name'))
    if command in SPECIAL or prop.tag == 'InputProperty':
        return
    getter = getattr(obj, 'Get' + command[3:], None)
    if prop.get('use_index') == '1':
        getter = getattr(obj, 'Get' + prop.get('name'))
    if getter is None:
        fail('%s: no getter for %s' % (name, command))
        return
    actual = getter()
    actual = list(actual) if isinstance(actual, (tuple, list)) else [actual]
    if prop.get('number_of_elements') == '0':
        # An empty property leaves the C++ default, which must then be "unset" (NaN).
        if not all(isinstance(a, float) and math.isnan(a) for a in actual):
            fail('%s: empty in XML but the C++ default is %s, not NaN' % (name, actual))
        return
    expected = values(prop.get('default_values', ''), prop.tag)
    if prop.tag == 'StringVectorProperty':
        actual = ['' if a is None else a for a in actual]
        expected = expected or ['']
    if prop.tag in ('IntVectorProperty', 'IdTypeVectorProperty'):
        actual = [int(a) for a in actual]
    if actual != expected:
        fail('%s: XML default %s, C++ default %s' % (name, expected, actual))
    check_domains(name, obj, prop, command)


def check_domains(name, obj, prop, command):
    for domain in prop:
        if domain.tag in ('IntRangeDomain', 'IdTypeRangeDomain') and hasattr(obj, 'Get%sMinValue' % command[3:]):
            lo = getattr(obj, 'Get%sMinValue' % command[3:])()
            hi = getattr(obj, 'Get%sMaxValue' % command[3:])()
            if domain.get('min') is not None and int(domain.get('min').split()[0]) != lo:
                fail('%s: XML minimum %s, C++ clamp minimum %s' % (name, domain.get('min'), lo))
            if domain.get('max') is not None and int(domain.get('max').split()[0]) != hi:
                fail('%s: XML maximum %s, C++ clamp maximum %s' % (name, domain.get('max'), hi))
        if domain.tag == 'EnumerationDomain':
            for entry in domain:
                setter = getattr(obj, 'Set%sTo%s' % (command[3:], entry.get('text')), None)
                if setter is None:
                    continue
                setter()
                got = getattr(obj, 'Get' + command[3:])()
                if int(got) != int(entry.get('value')):
                    fail('%s: entry %s is %s in XML, %s in C++' % (name, entry.get('text'),
                                                                   entry.get('value'), got))
            default = values(prop.get('default_values'), prop.tag)[0]
            getattr(obj, command)(default)


def module_classes():
    """The reader, filter and writer classes of the wrapped modules."""
    names = set()
    for name in dir(terroir):
        cls = getattr(terroir, name)
        # Terroir::Rendering is not in the plugin: ParaView renders.
        if name.startswith('vtkTerroir') and isinstance(cls, type) and \
                'Rendering' not in cls.__module__:
            if any(b.__name__ in ('vtkAlgorithm',) for b in cls.__mro__) or name in NO_PROXY:
                names.add(name)
    return names


def main():
    found = proxies(sys.argv[1])
    covered = set()
    for (group, _), (proxy, props) in sorted(found.items()):
        cls = proxy.get('class')
        covered.add(cls)
        if group.startswith(('internal', 'terroir_internal')):
            continue
        if not proxy.find('Documentation').get('short_help'):
            fail('%s: no documentation' % proxy.get('name'))
        obj = getattr(terroir, cls)()
        for prop in props:
            check_property(cls, obj, prop)
    algorithms = module_classes()
    missing = sorted(algorithms - covered - set(NO_PROXY))
    if missing:
        fail('classes without a proxy: %s' % ', '.join(missing))
    print('checked %d proxies, %d classes' % (len(found), len(algorithms)))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
