package dev.motionfusion.app.build

import com.android.manifmerger.ManifestMerger2
import com.android.manifmerger.ManifestSystemProperty
import com.android.manifmerger.MergingReport
import com.android.utils.StdLogger
import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.text
import org.w3c.dom.Element
import java.io.File
import javax.xml.parsers.DocumentBuilderFactory

/**
 * The Android Gradle Plugin's manifest merger (com.android.tools.build:manifest-merger, the release of
 * the AGP the Gradle files use) run on the app's source manifest and the manifests of the libraries
 * android-libs unpacked, with what AGP passes it for this app: the namespace, the application id as
 * package and `${applicationId}`, versionCode, versionName, minSdk and targetSdk (the values of
 * app/pom.xml, which AndroidStudioProjectTest holds equal to build.gradle.kts), tools: declarations
 * removed, and for a debug variant the DEBUGGABLE feature. What comes out is the manifest a Gradle
 * build puts in its APK and hands Robolectric (the `android.manifest` property under Gradle).
 *
 * Maven only: it reads the libraries android-libs unpacked (`android.libraries`).
 */
internal object AgpManifestMerger {
    /** Set where the libraries' manifests are at hand (the Maven build's tests). */
    val available: Boolean get() = BuildFiles.hasLibraries

    /** The build values AGP takes from build.gradle.kts, read where the Maven build keeps them. */
    data class AppValues(val namespace: String, val applicationId: String, val versionCode: String, val versionName: String, val minSdk: String, val targetSdk: String)

    fun appValues(root: File = BuildFiles.repositoryRoot): AppValues {
        val rootPom = BuildFiles.parse(File(root, "pom.xml"))
        val props = HashMap<String, String>()
        for (pom in listOf(rootPom, BuildFiles.parse(File(root, "app/pom.xml")))) {
            pom.child("properties")?.let { p -> p.children().forEach { props[it.tagName] = it.textContent.trim() } }
        }
        val pkg = props.getValue("android.package")
        return AppValues(pkg, pkg, props.getValue("app.versionCode"), rootPom.text("version")!!, props.getValue("android.minSdk"), props.getValue("android.targetSdk"))
    }

    private val cache = HashMap<Boolean, Element>()

    /** AGP's merged manifest of this app: the debug variant's with [debuggable]. */
    fun mergeApp(debuggable: Boolean): Element = cache.getOrPut(debuggable) {
        merge(File(BuildFiles.repositoryRoot, "app/src/main/AndroidManifest.xml"), BuildFiles.libraryFolders().map { it.resolve("AndroidManifest.xml") }, appValues(), debuggable)
    }

    fun merge(source: File, libraries: List<File>, values: AppValues, debuggable: Boolean): Element {
        val logger = StdLogger(StdLogger.Level.WARNING)
        val invoker = ManifestMerger2.newMerger(source, logger, ManifestMerger2.MergeType.APPLICATION)
            .setNamespace(values.namespace)
            .setOverride(ManifestSystemProperty.Document.PACKAGE, values.applicationId)
            .setOverride(ManifestSystemProperty.Manifest.VERSION_CODE, values.versionCode)
            .setOverride(ManifestSystemProperty.Manifest.VERSION_NAME, values.versionName)
            .setOverride(ManifestSystemProperty.UsesSdk.MIN_SDK_VERSION, values.minSdk)
            .setOverride(ManifestSystemProperty.UsesSdk.TARGET_SDK_VERSION, values.targetSdk)
            .withFeatures(ManifestMerger2.Invoker.Feature.REMOVE_TOOLS_DECLARATIONS)
        for (lib in libraries) invoker.addLibraryManifest(lib.parentFile.name, lib)
        if (debuggable) invoker.withFeatures(ManifestMerger2.Invoker.Feature.DEBUGGABLE)
        val report = invoker.merge()
        check(report.result.isSuccess) { "AGP's manifest merger failed:\n" + report.loggingRecords.joinToString("\n") }
        val xml = report.getMergedDocument(MergingReport.MergedManifestKind.MERGED)
        val f = DocumentBuilderFactory.newInstance().apply { isNamespaceAware = true }
        return f.newDocumentBuilder().parse(xml.byteInputStream()).documentElement
    }
}
