package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.componentClass
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.BeforeEach
import org.junit.jupiter.api.Test
import java.io.File
import java.net.URLClassLoader
import java.nio.file.FileSystems
import java.nio.file.Paths
import java.util.zip.ZipFile

/**
 * The APKs the Maven build packaged, against what the Gradle files make the Android Gradle Plugin
 * package: the Java resources (every jar's non-class files less AGP's default excludes, read from
 * AGP's own jar, and the excludes app/build.gradle.kts adds; ServiceLoader files merged), the
 * manifest's components, permissions and debuggable flag (AGP's merger, [AgpManifestMerger]), and
 * the signing schemes the debug signingConfig declares.
 *
 * It runs after `package` (app/pom.xml, Surefire execution apk-check in the integration-test phase,
 * so `mvn verify` and bin/test run it) and is Maven only.
 */
class MavenApkTest {
    @BeforeEach
    fun afterPackage() = assumeTrue(System.getProperty("maven.apk.check") == "true", "runs in the apk-check execution, after package")

    private val target: File get() = File(System.getProperty("maven.build.directory") ?: error("system property maven.build.directory not set (app/pom.xml)"))
    private val debugApk get() = File(target, "motion-fusion-debug.apk")
    private val root = BuildFiles.repositoryRoot

    /** AGP's default packaging excludes, from the AGP jar of the Gradle files' version (app/pom.xml copies it to target/tools). */
    private fun agpDefaultExcludes(): Set<String> {
        val jar = File(target, "tools/agp.jar")
        assertTrue(jar.isFile, "$jar missing (maven-dependency-plugin, execution r8-tool)")
        URLClassLoader(arrayOf(jar.toURI().toURL()), javaClass.classLoader).use { loader ->
            val utils = loader.loadClass("com.android.build.gradle.internal.packaging.PackagingOptionsUtilsKt")
            @Suppress("UNCHECKED_CAST")
            return utils.getMethod("getDefaultExcludes").invoke(null) as Set<String>
        }
    }

    /** AGP's matching (ParsedPackagingOptions.compileGlob): a pattern not starting with / or * is anchored at the root. */
    private fun excluded(patterns: Collection<String>, entry: String): Boolean = patterns.any { p ->
        val glob = if (p.startsWith("/") || p.startsWith("*")) p else "/$p"
        FileSystems.getDefault().getPathMatcher("glob:$glob").matches(Paths.get("/$entry"))
    }

    /** What AGP would package as Java resources from the jars of the Maven runtime class path and the app's classes. */
    private fun expectedJavaResources(): Map<String, List<String>> {
        val excludes = agpDefaultExcludes() + GradleMirror(root, null).packagingExcludesDeclared().map { it.first }
        val jars = File(target, "runtime-classpath.txt").readText().trim().split(':').filter { it.isNotEmpty() }.map(::File)
        val out = LinkedHashMap<String, MutableList<String>>()
        fun add(name: String, from: String) { if (!name.endsWith("/") && !name.endsWith(".class") && !excluded(excludes, name)) out.getOrPut(name) { ArrayList() } += from }
        File(target, "classes").walkTopDown().filter { it.isFile }.forEach { add(it.relativeTo(File(target, "classes")).invariantSeparatorsPath, "app") }
        for (jar in jars) ZipFile(jar).use { z ->
            // A Kotlin Multiplatform library's root artifact (common metadata only): Gradle resolves its -jvm jar instead.
            if (z.getEntry("META-INF/kotlin-project-structure-metadata.json") == null) z.entries().asSequence().forEach { add(it.name, jar.name) }
        }
        return out
    }

    private fun entries(apk: File): List<String> = ZipFile(apk).use { z -> z.entries().asSequence().map { it.name }.toList() }

    private fun isAndroidEntry(name: String) = name == "AndroidManifest.xml" || name == "resources.arsc" || name.startsWith("res/") ||
        Regex("classes\\d*\\.dex").matches(name)

    @Test
    fun `the debug APK carries the Java resources AGP would`() {
        assumeTrue(debugApk.isFile, "no debug APK: run after package")
        val expected = expectedJavaResources()
        val actual = entries(debugApk).filterNot(::isAndroidEntry).toSet()
        assertEquals(emptyList<String>(), (expected.keys - actual).sorted(), "AGP would package these, the Maven APK lacks them")
        assertEquals(emptyList<String>(), (actual - expected.keys).sorted(), "the Maven APK has these, AGP would not package them")
        // What Dispatchers.Main needs on the phone, and what the issue named.
        for (needed in listOf("META-INF/services/kotlinx.coroutines.internal.MainDispatcherFactory", "DebugProbesKt.bin", "kotlin/kotlin.kotlin_builtins")) assertTrue(needed in actual, needed)
        // A ServiceLoader file found in several jars is merged, as AGP merges it.
        ZipFile(debugApk).use { z ->
            for ((name, from) in expected) if (name.startsWith("META-INF/services/")) {
                val lines = z.getInputStream(z.getEntry(name)).bufferedReader().readLines().map { it.substringBefore('#').trim() }.filter { it.isNotEmpty() }
                val wanted = from.filter { it != "app" }.flatMap { jarName ->
                    val jar = File(target, "runtime-classpath.txt").readText().trim().split(':').map(::File).single { it.name == jarName }
                    ZipFile(jar).use { j -> j.getInputStream(j.getEntry(name)).bufferedReader().readLines().map { it.substringBefore('#').trim() }.filter { it.isNotEmpty() } }
                }
                assertEquals(wanted.sorted(), lines.sorted(), name)
            }
        }
    }

    @Test
    fun `the debug APK's manifest is AGP's debug manifest`() {
        assumeTrue(debugApk.isFile, "no debug APK: run after package")
        val dump = ProcessBuilder("aapt2", "dump", "xmltree", "--file", "AndroidManifest.xml", debugApk.path).redirectErrorStream(true).start()
        val text = dump.inputStream.bufferedReader().readText()
        assertEquals(0, dump.waitFor(), text)
        val apk = ApkManifest.parse(text)
        val agp = AgpManifestMerger.mergeApp(debuggable = true)
        val app = agp.children("application").single()
        val agpComponents = app.children().filter { it.tagName in setOf("activity", "service", "receiver", "provider") }.map { "${it.tagName} ${it.componentClass()}" }.toSet()
        val agpPermissions = agp.children("uses-permission").map { it.getAttributeNS(BuildFiles.ANDROID, "name") }.toSet()
        assertEquals(agpComponents.sorted(), apk.components.sorted())
        assertEquals(agpPermissions.sorted(), apk.usesPermissions.sorted())
        assertEquals(app.getAttributeNS(BuildFiles.ANDROID, "debuggable"), apk.debuggable, "AGP's debug APK is debuggable")
    }

    @Test
    fun `the APKs are signed with the schemes the Gradle files declare`() {
        val declared = GradleMirror(root, null).declaredSigningSchemes()
        val apks = listOf(debugApk, File(target, "motion-fusion-release.apk")).filter { it.isFile }
        assumeTrue(apks.isNotEmpty(), "no APK: run after package")
        for (apk in apks) {
            val p = ProcessBuilder("apksigner", "verify", "-v", apk.path).redirectErrorStream(true).start()
            val out = p.inputStream.bufferedReader().readText()
            assertEquals(0, p.waitFor(), out)
            for (n in 1..4) {
                val used = Regex("""Verified using v$n scheme \([^)]*\): (true|false)""").find(out)?.groupValues?.get(1)?.toBoolean()
                // apksigner signs v4 into a separate .idsig file; verify reports it only when that file is there.
                val actual = used ?: (n == 4 && File(apk.path + ".idsig").isFile)
                assertEquals(declared.getValue(n), actual, "${apk.name}: v$n scheme\n$out")
            }
        }
    }

    @Test
    fun `the release build gave R8 the rules the jars embed`() {
        val rules = File(target, "apk-release/jar-rules")
        assumeTrue(File(target, "motion-fusion-release.apk").isFile, "no release APK (mvn -Prelease)")
        val names = rules.list().orEmpty().toList()
        assertTrue(names.any { it.contains("kotlinx-coroutines-core") && it.contains("-r8-") }, "$names")
        assertTrue(names.any { it.contains("kotlinx-coroutines-android") && it.contains("-r8-from-") }, "$names")
    }
}

/** The parts of `aapt2 dump xmltree` of a binary manifest this test compares. */
internal class ApkManifest(val components: Set<String>, val usesPermissions: Set<String>, val debuggable: String) {
    companion object {
        fun parse(dump: String): ApkManifest {
            val components = HashSet<String>()
            val permissions = HashSet<String>()
            var debuggable = ""
            var element: String? = null
            var depth = 0
            var pkg = ""
            for (line in dump.lines()) {
                val e = Regex("""^(\s*)E: ([\w-]+)""").find(line)
                if (e != null) { element = e.groupValues[2]; depth = e.groupValues[1].length; continue }
                val a = Regex("""^\s*A: (?:http://schemas.android.com/apk/res/android:)?(\w+)(?:\(0x[0-9a-f]+\))?=(.*)$""").find(line) ?: continue
                val (name, raw) = a.destructured
                val value = raw.substringBefore(" (Raw:").trim().removeSurrounding("\"")
                when {
                    element == "manifest" && name == "package" -> pkg = value
                    element == "uses-permission" && name == "name" -> permissions += value
                    element == "application" && name == "debuggable" -> debuggable = if (value == "0xffffffff" || value == "true") "true" else value
                    element in setOf("activity", "service", "receiver", "provider") && name == "name" -> components += "$element ${BuildFiles.qualifiedName(value, pkg)}"
                }
            }
            return ApkManifest(components, permissions, debuggable)
        }
    }
}
