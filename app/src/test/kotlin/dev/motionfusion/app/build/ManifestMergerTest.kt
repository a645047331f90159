package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.manifestPackage
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import org.w3c.dom.Element
import java.io.File

/**
 * The Maven build writes the libraries' manifest entries into the app's manifest by hand and merges
 * nothing; the Android Gradle Plugin merges the libraries' manifests into the app's. This test runs
 * AGP's own merger ([AgpManifestMerger]) and fails unless its result and the Maven build's manifest
 * (the one aapt2 links into the APK and Robolectric reads) declare the same: package, versions,
 * SDK levels, permissions, features, application attributes and every component with its
 * attributes, intent filters, meta-data and properties (class names qualified, order ignored).
 *
 * One difference is by design and stated here: AGP's debug variant adds `android:debuggable="true"`
 * to `<application>`; the Maven build's manifest is shared by both APKs and the debug APK gets the
 * attribute from aapt2's `--debug-mode` when it is packaged (MavenApkTest checks the APK).
 */
class ManifestMergerTest {
    /** Attributes a build adds to one variant only, and why. */
    private val VARIANT_ONLY = mapOf(
        "application@debuggable" to "AGP's debug variant; the Maven debug APK gets it from aapt2 --debug-mode",
    )

    @Test
    fun `AGP's merger and the Maven build declare the same manifest`() {
        val maven = BuildFiles.parse(BuildFiles.manifest)
        val agp = AgpManifestMerger.mergeApp(debuggable = false)
        assertEquals("", difference(ManifestShape.of(maven), ManifestShape.of(agp)))
    }

    @Test
    fun `the debug variant differs only by debuggable, which is set`() {
        val release = ManifestShape.of(AgpManifestMerger.mergeApp(debuggable = false))
        val debug = ManifestShape.of(AgpManifestMerger.mergeApp(debuggable = true))
        assertTrue(debug.getValue("application").contains("debuggable=true"), debug.getValue("application"))
        assertEquals(release, ManifestShape.of(AgpManifestMerger.mergeApp(debuggable = true), ignore = VARIANT_ONLY.keys))
    }

    private fun difference(maven: Map<String, String>, agp: Map<String, String>): String = buildString {
        for (k in (maven.keys + agp.keys).sorted()) {
            val m = maven[k]
            val a = agp[k]
            if (m != a) append("$k\n  Maven: ${m ?: "(absent)"}\n  AGP:   ${a ?: "(absent)"}\n")
        }
    }

    // --- the test fails on a difference the Maven build could have ---

    @TempDir
    lateinit var dir: File

    /** The difference between the Maven build's manifest and AGP's merge of the source manifest after [edit]. */
    private fun differenceAfter(edit: (String) -> String): String {
        val source = File(BuildFiles.repositoryRoot, "app/src/main/AndroidManifest.xml")
        val copy = File(dir, "AndroidManifest.xml").apply { writeText(edit(source.readText())) }
        val agp = AgpManifestMerger.merge(copy, BuildFiles.libraryFolders().map { it.resolve("AndroidManifest.xml") }, AgpManifestMerger.appValues(), debuggable = false)
        return difference(ManifestShape.of(BuildFiles.parse(BuildFiles.manifest)), ManifestShape.of(agp))
    }

    @Test
    fun `a library entry the app declares differently is a difference`() {
        // The merger adds the libraries' own entries to the app's copy: equal only while the copy holds
        // exactly what they declare. Here the app's copy of androidx.startup's provider renames a meta-data.
        val diff = differenceAfter { it.replace("android:name=\"androidx.emoji2.text.EmojiCompatInitializer\"", "android:name=\"androidx.emoji2.text.Other\"") }
        assertTrue(diff.contains("provider androidx.startup.InitializationProvider"), diff)
    }

    @Test
    fun `a component attribute changed in the source is a difference`() {
        val diff = differenceAfter { it.replace("android:foregroundServiceType=\"connectedDevice\"", "android:foregroundServiceType=\"dataSync\"") }
        assertTrue(diff.contains("service dev.motionfusion.app.stream.StreamService"), diff)
    }
}

/**
 * A manifest as a map from each top-level declaration (`uses-permission X`, `activity C`,
 * `application`, `manifest`, `uses-sdk`) to a canonical text of its android: attributes and
 * children, sorted, with component class names qualified by the manifest's package and tools:
 * attributes left out: equal maps mean the same manifest to Android.
 */
internal object ManifestShape {
    private val COMPONENTS = setOf("activity", "activity-alias", "service", "receiver", "provider")
    /** Attributes holding a class name relative to the package. */
    private val CLASS_ATTRIBUTES = setOf("name", "targetActivity", "backupAgent", "manageSpaceActivity", "appComponentFactory", "parentActivityName")

    fun of(manifest: Element, ignore: Set<String> = emptySet()): Map<String, String> {
        val pkg = manifest.manifestPackage()
        val out = LinkedHashMap<String, String>()
        val manifestAttrs = attributes(manifest, pkg, "manifest", ignore, classNames = false).filterNot { it.startsWith("xmlns") }
        out["manifest"] = (listOf("package=$pkg") + manifestAttrs).sorted().joinToString(" ")
        for (e in manifest.children()) {
            when (e.tagName) {
                "application" -> {
                    out["application"] = attributes(e, pkg, "application", ignore, classNames = true).sorted().joinToString(" ")
                    for (c in e.children()) {
                        val key = if (c.tagName in COMPONENTS) "${c.tagName} ${name(c, pkg, true)}" else "application/${c.tagName} ${name(c, pkg, false)}"
                        check(key !in out) { "$key declared twice" }
                        out[key] = canonical(c, pkg, c.tagName in COMPONENTS)
                    }
                }
                else -> {
                    val key = "${e.tagName} ${name(e, pkg, false)}".trim()
                    check(key !in out) { "$key declared twice" }
                    out[key] = canonical(e, pkg, false)
                }
            }
        }
        return out
    }

    private fun name(e: Element, pkg: String, component: Boolean): String {
        val n = e.getAttributeNS(BuildFiles.ANDROID, "name")
        return if (component) BuildFiles.qualifiedName(n, pkg) else n
    }

    private fun attributes(e: Element, pkg: String, where: String, ignore: Set<String>, classNames: Boolean): List<String> {
        val out = ArrayList<String>()
        for (i in 0 until e.attributes.length) {
            val a = e.attributes.item(i)
            if (a.namespaceURI == BuildFiles.TOOLS || a.nodeName.startsWith("xmlns")) continue
            val local = a.localName ?: a.nodeName
            if ("$where@$local" in ignore) continue
            if (local == "package" && a.namespaceURI == null) continue
            val value = if (classNames && local in CLASS_ATTRIBUTES && a.namespaceURI == BuildFiles.ANDROID && a.nodeValue.isNotEmpty()) BuildFiles.qualifiedName(a.nodeValue, pkg) else a.nodeValue
            out += "$local=$value"
        }
        return out
    }

    private fun canonical(e: Element, pkg: String, component: Boolean): String {
        val attrs = attributes(e, pkg, e.tagName, emptySet(), classNames = component).sorted()
        val kids = e.children().map { canonical(it, pkg, false) }.sorted()
        return "<${e.tagName} ${attrs.joinToString(" ")}" + (if (kids.isEmpty()) "" else " " + kids.joinToString(" ")) + ">"
    }
}
