package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.text
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.w3c.dom.Element
import java.io.File

/**
 * The Android Studio project (settings.gradle.kts, build.gradle.kts files, gradle/libs.versions.toml)
 * is not built here, so nothing else would notice it drifting from the Maven build of record. This
 * test reads both and fails on any difference in modules, dependencies and their versions, source
 * and resource folders, SDK levels, application id, version and JVM target. It understands the
 * Gradle files in the forms they are written in and fails on a dependency line it cannot read.
 */
class AndroidStudioProjectTest {
    private val root = BuildFiles.repositoryRoot
    private val rootPom = BuildFiles.parse(File(root, "pom.xml"))

    /** Maven modules without a Gradle counterpart, and why. */
    private val mavenOnly = mapOf(
        "android-libs" to "Maven's way to resolve AARs; Gradle resolves the app's dependencies itself",
        "android-test-libs" to "as android-libs, for the tests",
        "fusion-bench" to "JMH over the app module's classes, which Gradle does not offer to a JVM module",
    )

    /** Maven dependencies the Gradle build does not need, and why. */
    private val mavenOnlyDependencies = mapOf(
        "org.codehaus.mojo:animal-sniffer" to "the API-level guard's checker (Android Studio has lint)",
        "com.toasttab.android:gummy-bears-api-26" to "the API-level guard's signature",
    )

    private data class Dep(val configuration: String, val coordinates: String, val version: String) {
        override fun toString() = "$configuration $coordinates:$version"
    }

    // --- Maven side ---

    private fun properties(pom: Element): Map<String, String> =
        pom.child("properties")?.children()?.associate { it.tagName to it.textContent.trim() }.orEmpty()

    private val rootProperties = properties(rootPom) + mapOf("project.version" to rootPom.text("version")!!)

    private fun interpolate(value: String, props: Map<String, String>): String =
        Regex("""\$\{([^}]+)}""").replace(value) { m -> props[m.groupValues[1]] ?: error("unknown property ${m.value}") }

    private val managed: Map<String, String> = rootPom.child("dependencyManagement")!!.child("dependencies")!!.children("dependency")
        .associate { "${it.text("groupId")}:${it.text("artifactId")}" to interpolate(it.text("version")!!, rootProperties) }

    private fun pom(module: String) = BuildFiles.parse(File(root, "$module/pom.xml"))

    private fun mavenDependencies(module: String): Set<Dep> {
        val pom = pom(module)
        val props = rootProperties + properties(pom)
        val out = HashSet<Dep>()
        for (d in pom.child("dependencies")!!.children("dependency")) {
            val ga = "${d.text("groupId")}:${d.text("artifactId")}"
            val scope = d.text("scope") ?: "compile"
            val version = d.text("version")?.let { interpolate(it, props) }
                ?: managed[ga]
                ?: (if (ga.startsWith("org.junit.")) managed["org.junit:junit-bom"] else null)
                ?: error("$module: no version for $ga")
            if (ga in mavenOnlyDependencies) continue
            if (scope == "provided" && ga == "org.robolectric:android-all") continue // the framework to compile against: compileSdk
            val configuration = if (scope == "test") "testImplementation" else "implementation"
            if (ga.startsWith("dev.motionfusion:android-")) {
                // The AndroidX lists: what the app asks for, at the versions the lists give.
                val libs = pom(ga.substringAfter(':'))
                val versions = libs.child("dependencies")!!.children("dependency")
                    .associate { "${it.text("groupId")}:${it.text("artifactId")}" to it.text("version")!! }
                for (used in properties(libs).getValue("app.uses").split(',')) out += Dep(configuration, used, versions.getValue(used))
            } else {
                out += Dep(configuration, ga, version)
            }
        }
        return out
    }

    // --- Gradle side ---

    private val toml: Map<String, Map<String, String>> = run {
        val sections = HashMap<String, MutableMap<String, String>>()
        var section = ""
        for (raw in File(root, "gradle/libs.versions.toml").readLines()) {
            val line = raw.substringBefore('#').trim()
            if (line.isEmpty()) continue
            if (line.startsWith("[")) { section = line.trim('[', ']'); continue }
            sections.getOrPut(section) { LinkedHashMap() }[line.substringBefore('=').trim()] = line.substringAfter('=').trim()
        }
        sections
    }

    private fun tomlField(entry: String, field: String): String? = Regex("""$field\s*=\s*"([^"]*)"""").find(entry)?.groupValues?.get(1)

    private fun version(ref: String): String = toml.getValue("versions")[ref]?.trim('"') ?: error("no version $ref in libs.versions.toml")

    /** `libs.androidx.core.ktx` → coordinates and version (a BOM-managed library takes the BOM's version). */
    private fun library(accessor: String, bomVersion: String?): Pair<String, String> {
        val alias = toml.getValue("libraries").keys.single { it.replace('-', '.').replace('_', '.') == accessor }
        val entry = toml.getValue("libraries").getValue(alias)
        val module = tomlField(entry, "module") ?: error("$alias: no module")
        val v = tomlField(entry, "version.ref")?.let(::version) ?: bomVersion ?: error("$alias: no version and no BOM")
        return module to v
    }

    private fun gradleFile(module: String) = File(root, "$module/build.gradle.kts").readText()

    private fun gradleDependencies(module: String): Set<Dep> {
        val text = gradleFile(module)
        val block = text.substringAfter("\ndependencies {").substringBefore("\n}")
        val lines = block.lines().map { it.trim() }.filter { it.isNotEmpty() && !it.startsWith("//") }
        val bom = lines.firstNotNullOfOrNull { Regex("""\w+\(platform\(libs\.([\w.]+)\)\)""").matchEntire(it)?.groupValues?.get(1) }
            ?.let { library(it, null).second }
        val out = HashSet<Dep>()
        for (line in lines) {
            val m = Regex("""(implementation|testImplementation)\((.*)\)""").matchEntire(line) ?: error("$module/build.gradle.kts: cannot read '$line'")
            val (configuration, arg) = m.destructured
            when {
                arg.startsWith("platform(") -> Unit
                arg.startsWith("project(") -> {
                    val p = Regex("""project\(":([\w-]+)"\)""").matchEntire(arg)!!.groupValues[1]
                    out += Dep(configuration, "dev.motionfusion:$p", rootProperties.getValue("project.version"))
                }
                arg.startsWith("libs.") -> library(arg.removePrefix("libs."), bom).let { (ga, v) -> out += Dep(configuration, ga, v) }
                else -> error("$module/build.gradle.kts: cannot read '$line'")
            }
        }
        return out
    }

    private fun gradleValue(text: String, name: String): String =
        Regex("""\b$name\s*=\s*"?([^"\n]+)"?""").find(text)?.groupValues?.get(1)?.trim() ?: error("$name not set")

    // --- the comparisons ---

    @Test
    fun `the same modules`() {
        val maven = rootPom.child("modules")!!.children("module").map { it.textContent.trim() }.toSet() - mavenOnly.keys
        val gradle = Regex("""include\("(:[\w-]+)"\)""").findAll(File(root, "settings.gradle.kts").readText()).map { it.groupValues[1].removePrefix(":") }.toSet()
        assertEquals(maven, gradle)
    }

    @Test
    fun `the same dependencies at the same versions`() {
        for (module in listOf("fusion-core", "fusion-cli", "app")) {
            assertEquals(mavenDependencies(module).sortedBy { it.toString() }, gradleDependencies(module).sortedBy { it.toString() }, module)
        }
    }

    @Test
    fun `the same Kotlin version and JVM target`() {
        val plugin = toml.getValue("plugins").getValue("kotlin-jvm")
        assertEquals(rootProperties.getValue("kotlin.version"), version(tomlField(plugin, "version.ref")!!))
        for (module in listOf("fusion-core", "fusion-cli", "app")) {
            assertEquals(rootProperties.getValue("kotlin.compiler.jvmTarget"), Regex("""jvmToolchain\((\d+)\)""").find(gradleFile(module))?.groupValues?.get(1), module)
        }
    }

    @Test
    fun `the same application id, version, SDK levels and folders`() {
        val app = gradleFile("app")
        val props = rootProperties + properties(pom("app"))
        assertEquals(props.getValue("android.package"), gradleValue(app, "applicationId"))
        assertEquals(props.getValue("android.package"), gradleValue(app, "namespace"))
        assertEquals(props.getValue("android.minSdk"), gradleValue(app, "minSdk"))
        assertEquals(props.getValue("android.targetSdk"), gradleValue(app, "targetSdk"))
        assertEquals(props.getValue("android.compileSdk"), gradleValue(app, "compileSdk"))
        val apiOfRelease = mapOf("13" to "33", "14" to "34", "15" to "35", "16" to "36")
        assertEquals(props.getValue("android.compileSdk"), apiOfRelease[props.getValue("android.all.version").substringBefore('-')], "android-all's release is compileSdk")
        assertEquals(props.getValue("app.versionCode"), gradleValue(app, "versionCode"))
        assertEquals(props.getValue("project.version"), gradleValue(app, "versionName"))
        val appPom = File(root, "app/pom.xml").readText()
        for (dir in Regex("""srcDirs?\("([^"]+)"\)|srcFile\("([^"]+)"\)""").findAll(app).map { it.groupValues.drop(1).first { g -> g.isNotEmpty() } }) {
            assertTrue(File(root, "app/$dir").exists(), "app/$dir")
            val mavenNamesIt = dir == "src/main/kotlin" || dir == "src/test/kotlin" || appPom.contains("\${project.basedir}/$dir") || appPom.contains("<directory>$dir</directory>")
            assertTrue(mavenNamesIt, "app/pom.xml does not use app/$dir")
        }
        for (module in listOf("fusion-core", "fusion-cli")) {
            val dirs = Regex("""srcDirs\("([^"]+)"\)""").findAll(gradleFile(module)).map { it.groupValues[1] }.toSet()
            assertEquals(setOf("src/main/kotlin", "src/test/kotlin"), dirs, module)
        }
    }
}
