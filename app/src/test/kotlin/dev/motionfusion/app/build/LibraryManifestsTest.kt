package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.androidAttributes
import dev.motionfusion.app.build.BuildFiles.androidName
import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.w3c.dom.Element

/**
 * Without the Android Gradle Plugin nothing merges the libraries' manifests into the app's, so
 * the app's manifest carries their entries itself. This test reads every library manifest of
 * android-libs and fails on an entry (permission, uses-permission, application attribute,
 * provider with its meta-data, receiver with its actions, service, activity) that the app's
 * manifest lacks or declares differently, unless [LEFT_OUT] says why it is left out; on an
 * androidx entry of the app that no library declares; and on a library that needs a higher
 * minSdk than the app's.
 */
class LibraryManifestsTest {
    private val app = BuildFiles.parse(BuildFiles.manifest)
    private val appPackage = app.getAttribute("package")
    private val appApplication = app.child("application")!!

    /** Library entries deliberately not in the app's manifest, with the reason. None today. */
    private val LEFT_OUT = emptyMap<String, String>()

    private class Entry(val library: String, val kind: String, val element: Element) {
        val name: String get() = element.androidName()
        override fun toString() = "$kind $name (from $library)"
    }

    private fun libraryEntries(): List<Entry> = BuildFiles.libraryFolders().flatMap { dir ->
        val m = BuildFiles.parse(dir.resolve("AndroidManifest.xml"))
        val lib = dir.name
        m.children("permission").map { Entry(lib, "permission", it) } +
            m.children("uses-permission").map { Entry(lib, "uses-permission", it) } +
            m.children("application").flatMap { a ->
                listOf("provider", "receiver", "service", "activity").flatMap { k -> a.children(k).map { Entry(lib, k, it) } }
            }
    }

    private fun resolve(value: String) = value.replace("\${applicationId}", appPackage)

    private fun appEntry(kind: String, name: String): Element? {
        val parent = if (kind == "permission" || kind == "uses-permission") app else appApplication
        return parent.children(kind).firstOrNull { resolve(it.androidName()).let { n -> n == name || appPackage + n == name } }
    }

    @Test
    fun `every entry of the libraries' manifests is in the app's or left out for a stated reason`() {
        val entries = libraryEntries()
        assertTrue(entries.size >= 4, "expected androidx.core's permission and androidx.startup's provider among $entries")
        val problems = ArrayList<String>()
        for (e in entries) {
            val name = resolve(e.name)
            if (name in LEFT_OUT) continue
            val mine = appEntry(e.kind, name)
            if (mine == null) {
                problems += "$e: missing from app/src/main/AndroidManifest.xml"
                continue
            }
            for ((attr, value) in e.element.androidAttributes()) {
                if (attr == "name") continue
                val have = mine.getAttributeNS(BuildFiles.ANDROID, attr)
                if (resolve(have) != resolve(value)) problems += "$e: android:$attr is '$have', the library says '${resolve(value)}'"
            }
            val wantedMeta = e.element.children("meta-data").map { it.androidName() to it.getAttributeNS(BuildFiles.ANDROID, "value") }
            val haveMeta = mine.children("meta-data").map { it.androidName() to it.getAttributeNS(BuildFiles.ANDROID, "value") }.toSet()
            for (m in wantedMeta) if (m !in haveMeta && m.first !in LEFT_OUT) problems += "$e: meta-data ${m.first} missing"
            val actions = { el: Element -> el.children("intent-filter").flatMap { f -> f.children("action").map { it.androidName() } }.toSet() }
            if (actions(e.element) != actions(mine)) problems += "$e: actions ${actions(mine)}, the library says ${actions(e.element)}"
        }
        assertEquals(emptyList<String>(), problems)
    }

    @Test
    fun `application attributes the libraries set are the app's too`() {
        val wanted = BuildFiles.libraryFolders().flatMap { dir ->
            BuildFiles.parse(dir.resolve("AndroidManifest.xml")).children("application").flatMap { it.androidAttributes().entries }
        }
        assertTrue(wanted.any { it.key == "appComponentFactory" }, "androidx.core sets android:appComponentFactory")
        for ((attr, value) in wanted) assertEquals(value, appApplication.getAttributeNS(BuildFiles.ANDROID, attr), "application android:$attr")
    }

    @Test
    fun `every androidx entry of the app's manifest comes from a library`() {
        val declared = libraryEntries().map { it.kind to resolve(it.name) }.toSet()
        for (kind in listOf("provider", "receiver", "service", "activity")) {
            for (el in appApplication.children(kind)) {
                val name = el.androidName()
                if (name.startsWith("androidx.") || name.startsWith("com.google.")) {
                    assertTrue(kind to name in declared, "$kind $name is in the app's manifest but no library declares it")
                }
            }
        }
    }

    @Test
    fun `no library needs a higher minSdk than the app`() {
        val appMin = app.child("uses-sdk")!!.getAttributeNS(BuildFiles.ANDROID, "minSdkVersion").toInt()
        for (dir in BuildFiles.libraryFolders()) {
            val min = BuildFiles.parse(dir.resolve("AndroidManifest.xml")).child("uses-sdk")
                ?.getAttributeNS(BuildFiles.ANDROID, "minSdkVersion")?.toIntOrNull() ?: 1
            assertTrue(min <= appMin, "${dir.name} needs minSdk $min, the app has $appMin")
        }
    }
}
