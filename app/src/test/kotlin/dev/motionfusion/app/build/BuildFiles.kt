package dev.motionfusion.app.build

import org.junit.jupiter.api.Assertions.assertTrue
import org.w3c.dom.Element
import java.io.File
import javax.xml.parsers.DocumentBuilderFactory

/** The files the build made or read, as Surefire passes them (app/pom.xml), and XML helpers for the build tests. */
internal object BuildFiles {
    private fun path(property: String): File {
        val value = System.getProperty(property)
        check(!value.isNullOrEmpty()) { "system property $property not set (Surefire sets it; see app/pom.xml)" }
        return File(value)
    }

    /** The app's manifest as the APK gets it (versions and SDK levels filled in). */
    val manifest: File get() = path("android.manifest")

    /** The unpacked AARs of android-libs, one folder each, listed in dependency order in libraries.txt. */
    val libraries: File get() = path("android.libraries")

    val repositoryRoot: File get() = path("project.root")

    /** Whether this run has the unpacked AARs (the Maven build's tests do; Gradle's merge libraries themselves). */
    val hasLibraries: Boolean get() = !System.getProperty(LIBRARIES).isNullOrEmpty()

    private const val LIBRARIES = "android.libraries"

    val localRepository: File get() = path("maven.repo.local")

    val apiSignature: File get() = path("android.api.signature")

    fun libraryFolders(): List<File> {
        val list = File(libraries, "libraries.txt")
        assertTrue(list.isFile, "$list missing: android-libs is built before the app")
        return list.readLines().filter { it.isNotBlank() }.map { File(it.substringBefore(' ')) }
    }

    fun parse(file: File): Element {
        val f = DocumentBuilderFactory.newInstance().apply { isNamespaceAware = true }
        return f.newDocumentBuilder().parse(file).documentElement
    }

    const val ANDROID = "http://schemas.android.com/apk/res/android"
    const val TOOLS = "http://schemas.android.com/tools"

    fun Element.children(tag: String? = null): List<Element> {
        val out = ArrayList<Element>()
        val nodes = childNodes
        for (i in 0 until nodes.length) {
            val n = nodes.item(i)
            if (n is Element && (tag == null || n.tagName == tag)) out.add(n)
        }
        return out
    }

    fun Element.child(tag: String): Element? = children(tag).firstOrNull()

    fun Element.text(tag: String): String? = child(tag)?.textContent?.trim()

    fun Element.androidName(): String = getAttributeNS(ANDROID, "name")

    /**
     * A component's class as Android reads it: `.record.RecordingService` and `RecordingService` (no dot)
     * are relative to [pkg]. The Maven build's manifest keeps the names as written; the Android Gradle
     * Plugin's merger writes them out in full, so tests compare names through this.
     */
    fun qualifiedName(name: String, pkg: String): String = when {
        name.startsWith(".") -> pkg + name
        !name.contains('.') -> "$pkg.$name"
        else -> name
    }

    /** The manifest's package (Maven's manifest and AGP's merged one both carry it). */
    fun Element.manifestPackage(): String = getAttribute("package").also { check(it.isNotEmpty()) { "the manifest has no package attribute" } }

    /** This component's class name, qualified with the package of the manifest it sits in. */
    fun Element.componentClass(): String = qualifiedName(androidName(), ownerDocument.documentElement.manifestPackage())

    /** android:* attributes, values as written. */
    fun Element.androidAttributes(): Map<String, String> {
        val out = LinkedHashMap<String, String>()
        for (i in 0 until attributes.length) {
            val a = attributes.item(i)
            if (a.namespaceURI == ANDROID) out[a.localName] = a.nodeValue
        }
        return out
    }
}
